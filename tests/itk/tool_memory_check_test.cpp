// Before its large allocations a run compares what it still needs with the
// memory available (the system's, its control group's, its address-space
// limit's) and refuses in one line, exit code 6, when it cannot fit;
// --no-memory-check runs anyway. --stats reports the estimate, which bounds
// the measured peak from above without overstating it wildly.
#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <sstream>

#include "test_support.hpp"

namespace stvd::testing {
namespace {

constexpr int kMemory = 6;

class ToolMemoryCheck : public ScratchFolderTest {
 protected:
  const std::string brain = sampleFile("dti_tensor_dipy5d.nii.gz");

  /// A number field of the statistics file.
  static double field(const std::string& json, const std::string& name) {
    std::smatch m;
    if (!std::regex_search(json, m, std::regex("\"" + name + "\": ([0-9.]+)"))) return -1;
    return std::stod(m[1]);
  }
  std::string statsOf(const std::vector<std::string>& options) {
    std::vector<std::string> args{"distance", brain, "--seed-voxel", "55,54,15", "-o", path("d.nii.gz"),
                                  "--stats", path("s.json"), "-q"};
    args.insert(args.end(), options.begin(), options.end());
    const ToolRun run = runTool(args);
    EXPECT_EQ(run.exitCode, 0) << run.err;
    std::ifstream in(path("s.json"));
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }
};

TEST_F(ToolMemoryCheck, TheEstimateBoundsTheMeasuredPeak) {
  // Measured: STVD 86 MiB estimated for a 69 MiB peak, Lanthier M = 2
  // 133 MiB for 102 MiB (1.2 to 1.3 times).
  for (const std::vector<std::string>& options :
       {std::vector<std::string>{}, std::vector<std::string>{"--method", "lanthier", "--steiner", "2"}}) {
    const std::string json = statsOf(options);
    const double estimate = field(json, "needed_bytes") + field(json, "resident_bytes");
    const double peak = field(json, "peak_memory_bytes");
    EXPECT_GT(field(json, "needed_bytes"), 0) << json;
    EXPECT_GE(estimate, peak) << json;
    EXPECT_LE(estimate, 1.6 * peak) << json;
    EXPECT_NE(json.find("\"check\": \"passed\""), std::string::npos) << json;
  }
}

TEST_F(ToolMemoryCheck, ARunThatCannotFitIsRefusedBeforeItStarts) {
  // Lanthier's method with M = 16 on the brain needs 817 graph points per
  // domain voxel, about 2.5 GiB; the address space is limited to 1 GiB.
  const std::vector<std::string> args{"distance", brain, "--seed-voxel", "55,54,15", "--method", "lanthier",
                                      "--steiner", "16", "-o", path("d.nii.gz")};
  const ToolRun run = runToolInBash("ulimit -v 1048576; exec \"$0\" \"$@\"", args);
  EXPECT_EQ(run.exitCode, kMemory) << run.err;
  EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << run.err;
  EXPECT_EQ(run.err.rfind("stvd: " + brain + ": the run needs about ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find("address-space limit"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("--no-memory-check"), std::string::npos) << run.err;
  EXPECT_TRUE(listFolder(folder()).empty());

  // Told to run anyway, it tries, and the allocation itself fails.
  std::vector<std::string> anyway = args;
  anyway.push_back("--no-memory-check");
  const ToolRun tried = runToolInBash("ulimit -v 1048576; exec \"$0\" \"$@\"", anyway);
  EXPECT_EQ(tried.exitCode, kMemory) << tried.err;
  EXPECT_EQ(tried.err.rfind("stvd: out of memory", 0), 0u) << tried.err;
  EXPECT_TRUE(listFolder(folder()).empty());
}

}  // namespace
}  // namespace stvd::testing
