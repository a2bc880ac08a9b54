// The files behind an image path (stvd/imaging/image_files.hpp): what the tool
// compares with its outputs before it reads anything, so it reads headers
// that nothing has checked yet.
#include "stvd/imaging/image_files.hpp"

#include <fstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace stvd::testing {
namespace {

class ImageFiles : public ScratchFolderTest {
 protected:
  std::string writeNrrdHeader(const std::string& name, const std::string& dataFileField) {
    std::ofstream(path(name)) << "NRRD0004\ntype: float\ndimension: 1\nsizes: 4\nencoding: raw\ndata file: "
                              << dataFileField << "\n\n";
    return path(name);
  }
};

TEST_F(ImageFiles, ADetachedNrrdHeaderNamesItsDataFileBesideIt) {
  const std::string header = writeNrrdHeader("t.nhdr", "t.raw");
  EXPECT_EQ(imaging::imageFilesRead(header), (std::vector<std::string>{header, path("t.raw")}));
}

TEST_F(ImageFiles, ANrrdNamePatternNamesEveryFileItGenerates) {
  const std::string header = writeNrrdHeader("t.nhdr", "slice%03d.raw 1 7 3");
  EXPECT_EQ(imaging::imageFilesRead(header),
            (std::vector<std::string>{header, path("slice001.raw"), path("slice004.raw"), path("slice007.raw")}));
}

// Found by fuzzing: the numbers of a pattern spanning the whole range of a
// 64-bit integer overflowed (undefined behaviour, caught by UBSan). Only the
// numbers that exist are named.
TEST_F(ImageFiles, ANrrdNamePatternBeyondTheRangeOfIntegersStopsAtItsEnd) {
  const std::string header =
      writeNrrdHeader("t.nhdr", "d%d.raw -9223372036854775808 9223372036854775807 4611686018427387904");
  EXPECT_EQ(imaging::imageFilesRead(header),
            (std::vector<std::string>{header, path("d-9223372036854775808.raw"), path("d-4611686018427387904.raw"),
                                      path("d0.raw"), path("d4611686018427387904.raw")}));
}

}  // namespace
}  // namespace stvd::testing
