// stvd/files/file_identity.hpp: an output is compared with the inputs by
// what file it is, not by how it is spelled.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "stvd/files/file_identity.hpp"

namespace stvd::files {
namespace {

namespace fs = std::filesystem;

class FileIdentity : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = fs::temp_directory_path() / ("stvd_identity_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(root_);
    fs::create_directories(root_ / "data");
    fs::create_directories(root_ / "out");
    std::ofstream(path("data/t.nii.gz")) << "tensors";
    previous_ = fs::current_path();
    fs::current_path(root_ / "out");  // relative spellings start here
  }
  void TearDown() override {
    fs::current_path(previous_);
    fs::remove_all(root_);
  }
  std::string path(const std::string& relative) const { return (root_ / relative).string(); }

  fs::path root_, previous_;
};

TEST_F(FileIdentity, AnExistingFileIsItselfHoweverItIsSpelled) {
  EXPECT_TRUE(sameFile(path("data/t.nii.gz"), "../data/t.nii.gz"));
  EXPECT_TRUE(sameFile(path("data/t.nii.gz"), "./../data/./t.nii.gz"));
  EXPECT_TRUE(sameFile(path("data/t.nii.gz"), path("out/../data/t.nii.gz")));
}

TEST_F(FileIdentity, SymbolicAndHardLinksAreTheFileTheyLeadTo) {
  fs::create_symlink(path("data/t.nii.gz"), path("out/link.nii.gz"));
  fs::create_hard_link(path("data/t.nii.gz"), path("out/hard.nii.gz"));
  fs::create_directory_symlink(path("data"), path("out/linked_data"));
  EXPECT_TRUE(sameFile("link.nii.gz", path("data/t.nii.gz")));
  EXPECT_TRUE(sameFile("hard.nii.gz", path("data/t.nii.gz")));
  EXPECT_TRUE(sameFile("linked_data/t.nii.gz", path("data/t.nii.gz")));
}

TEST_F(FileIdentity, NewFilesAreComparedByTheirCanonicalPath) {
  fs::create_directory_symlink(path("data"), path("out/linked_data"));
  EXPECT_TRUE(sameFile("new.nii", path("out/new.nii")));
  EXPECT_TRUE(sameFile("linked_data/new.nii", path("data/new.nii")));
  EXPECT_TRUE(sameFile("../out/./new.nii", "new.nii"));
  EXPECT_FALSE(sameFile("new.nii", "other.nii"));
  EXPECT_FALSE(sameFile("new.nii", path("data/t.nii.gz")));
}

TEST_F(FileIdentity, AnOutputThatIsAnInputIsAConflictNamingBothRoles) {
  const std::vector<RunFile> inputs{{"tensor input", path("data/t.nii.gz")}, {"mask", path("data/mask.nii.gz")}};
  try {
    checkOutputsAreNotInputs(inputs, {{"distance map", "../data/t.nii.gz"}});
    FAIL() << "no conflict";
  } catch (const FileConflict& e) {
    EXPECT_EQ(std::string(e.what()), "../data/t.nii.gz: the distance map is the tensor input (" +
                                         path("data/t.nii.gz") +
                                         ", the same file); stvd never writes over an input, choose another "
                                         "output file");
  }
  // A mask that does not exist yet is still an input the output must not be.
  EXPECT_THROW(checkOutputsAreNotInputs(inputs, {{"distance map", path("data/mask.nii.gz")}}), FileConflict);
  EXPECT_NO_THROW(checkOutputsAreNotInputs(inputs, {{"distance map", "d.nii.gz"}, {"statistics file", "s.json"}}));
}

TEST_F(FileIdentity, TwoOutputsThatAreOneFileAreAConflict) {
  try {
    checkOutputsAreNotInputs({}, {{"distance map", "d.nii.gz"}, {"statistics file", "./d.nii.gz"}});
    FAIL() << "no conflict";
  } catch (const FileConflict& e) {
    EXPECT_NE(std::string(e.what()).find("./d.nii.gz: the statistics file is the distance map"), std::string::npos)
        << e.what();
  }
}

TEST_F(FileIdentity, AnInputMayBeGivenInSeveralRoles) {
  EXPECT_NO_THROW(checkOutputsAreNotInputs(
      {{"mask", path("data/t.nii.gz")}, {"seed labels", "../data/t.nii.gz"}}, {{"distance map", "d.nii.gz"}}));
}

}  // namespace
}  // namespace stvd::files
