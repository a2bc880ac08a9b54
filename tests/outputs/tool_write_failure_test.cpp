// A write that fails - a full disk, a file-size limit - is exit code 5 and
// one line naming the file, and leaves every output path of the run as it
// was before: no partial file, no temporary file, the previous file
// unchanged. The outputs of a run appear together or not at all.
//
// The failures are real: the tool runs under `ulimit -f` with SIGXFSZ
// ignored, so that every write beyond the limit fails with EFBIG, as it
// does with ENOSPC on a full disk. Before it, a successful run has put
// files at the same paths.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "small_inputs.hpp"

namespace stvd::testing {
namespace {

namespace fs = std::filesystem;

constexpr int kOutput = 5;

class ToolWriteFailure : public SmallInputsTest {
 protected:
  /// Runs `arguments` once normally and marks what it wrote as earlier
  /// outputs, then runs them again with every file limited to `limitKiB`
  /// KiB, and expects the second run to fail writing `mentioned` and to
  /// leave "out/" exactly as it was.
  void expectFailureLeavesOutputsAsTheyWere(const std::vector<std::string>& arguments, const std::string& mentioned,
                                            int limitKiB = 0) {
    const ToolRun good = runTool(arguments);
    ASSERT_EQ(good.exitCode, 0) << good.err;
    // Marked, so that they differ from anything a run could write.
    for (const auto& entry : fs::directory_iterator(path("out")))
      std::ofstream(entry.path(), std::ios::app) << "\nan earlier output\n";
    const FolderSnapshot before = snapshot(path("out"));
    ASSERT_FALSE(before.empty());
    // The limit holds for every regular file the tool writes, its captured
    // stderr included, so stderr goes through a pipe (stdout is unused: -q).
    const ToolRun run = runToolInBash("(ulimit -f " + std::to_string(limitKiB) +
                                          "; trap '' XFSZ; exec \"$0\" \"$@\" 2>&1 >/dev/null) | cat >&2; "
                                          "exit ${PIPESTATUS[0]}",
                                      arguments);
    EXPECT_EQ(run.exitCode, kOutput) << run.err;
    // The tool's own line is the last one; niftilib may print its own
    // complaint first ("** ERROR: NWAD: wrote only ...").
    const std::string lastLine = run.err.substr(run.err.rfind('\n', run.err.size() - 2) + 1);
    EXPECT_EQ(lastLine.rfind("stvd", 0), 0u) << run.err;
    EXPECT_NE(lastLine.find(mentioned + ": "), std::string::npos) << run.err;
    EXPECT_TRUE(snapshot(path("out")) == before) << "the failed run changed out/: " << run.err;
  }
};

TEST_F(ToolWriteFailure, DistanceMapsInEveryImageFormat) {
  for (const std::string name : {"d.nii", "d.nii.gz", "d.nrrd", "d.nhdr"}) {
    SCOPED_TRACE(name);
    expectFailureLeavesOutputsAsTheyWere(distanceRun(out(name), out("d.json")), out(name));
  }
}

TEST_F(ToolWriteFailure, DistanceMapsAsMrtrixImages) {
  for (const std::string name : {"d.mif", "d.mif.gz"}) {
    SCOPED_TRACE(name);
    expectFailureLeavesOutputsAsTheyWere(distanceRun(out(name), out("d.json")), out(name));
  }
}

TEST_F(ToolWriteFailure, DistanceMapsAsOpenVdbGrids) {
  if (!withVdb()) GTEST_SKIP() << "built without OpenVDB";
  expectFailureLeavesOutputsAsTheyWere(distanceRun(out("d.vdb"), out("d.json")), out("d.vdb"));
}

TEST_F(ToolWriteFailure, AStatisticsFileThatFailsTakesTheDistanceMapWithIt) {
  // 54 seed voxels make the statistics (about 6 KiB) larger than the map
  // (3.1 KiB): with a 4 KiB limit the map is written and the statistics
  // are not, and neither may appear.
  std::vector<std::string> run{"distance", in("t.nii"), "--tensor-kind", "metric", "--seeds", in("labels.nii"),
                               "-o", out("d.nii"), "--stats", out("d.json"), "-q"};
  expectFailureLeavesOutputsAsTheyWere(run, out("d.json"), 4);
}

TEST_F(ToolWriteFailure, PathsAndTheirTable) {
  for (const std::string name : {"p.trk", "p.tck", "p.vtk"}) {
    SCOPED_TRACE(name);
    expectFailureLeavesOutputsAsTheyWere(pathRun(out(name), out("p.tsv")), out(name));
  }
}

TEST_F(ToolWriteFailure, ConnectivityTable) {
  expectFailureLeavesOutputsAsTheyWere(connectivityRun(out("c.tsv")), out("c.tsv"));
}

TEST_F(ToolWriteFailure, ConnectivityTableWithItsMatrices) {
  std::vector<std::string> run = connectivityRun(out("c.tsv"));
  run.insert(run.end(), {"--matrix", out("d.csv"), "--matrix-index", out("i.csv")});
  expectFailureLeavesOutputsAsTheyWere(run, out("c.tsv"));
}

TEST_F(ToolWriteFailure, TetMeshDistances) {
  for (const std::string name : {"m.vtk", "m.vtu", "m.csv"}) {
    SCOPED_TRACE(name);
    expectFailureLeavesOutputsAsTheyWere(tetMeshRun(out(name)), out(name));
  }
  std::vector<std::string> resampled = tetMeshRun(out("m.nii.gz"));
  resampled.insert(resampled.end(), {"--reference", in("mask.nii")});
  expectFailureLeavesOutputsAsTheyWere(resampled, out("m.nii.gz"));
}

TEST_F(ToolWriteFailure, SurfaceDistances) {
  for (const std::string name : {"s.ply", "s.vtk", "s.csv"}) {
    SCOPED_TRACE(name);
    expectFailureLeavesOutputsAsTheyWere(surfaceRun(out(name)), out(name));
  }
}

TEST_F(ToolWriteFailure, SurfaceStatisticsThatFailTakeTheDistancesWithThem) {
  // The 16-vertex table (0.2 KiB) fits under a 1 KiB limit; the statistics,
  // which list the 16 seeds, (about 1.5 KiB) do not: neither may appear.
  std::vector<std::string> run = surfaceRun(out("s.csv"));
  for (int v = 1; v < 16; ++v) run.insert(run.end(), {"--seed-vertex", std::to_string(v)});
  run.insert(run.end(), {"--stats", out("s.json")});
  expectFailureLeavesOutputsAsTheyWere(run, out("s.json"), 1);
}

TEST_F(ToolWriteFailure, TetrahedralizedMeshes) {
  if (!withTetrahedralize()) GTEST_SKIP() << "built without TetGen";
  expectFailureLeavesOutputsAsTheyWere(tetrahedralizeRun(out("box")), out("box.node"));
}

TEST_F(ToolWriteFailure, ANhdrNeverReplacesADataFileThatIsNotItsOwn) {
  std::ofstream(out("d.raw.gz")) << "someone else's data";
  const FolderSnapshot before = snapshot(path("out"));
  const ToolRun run = runTool(distanceRun(out("d.nhdr")));
  EXPECT_EQ(run.exitCode, kOutput) << run.err;
  EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << run.err;
  EXPECT_NE(run.err.find("would replace " + out("d.raw.gz")), std::string::npos) << run.err;
  EXPECT_TRUE(snapshot(path("out")) == before);
  // Its own data file, from an earlier run, is replaced with the header.
  fs::remove(out("d.raw.gz"));
  ASSERT_EQ(runTool(distanceRun(out("d.nhdr"))).exitCode, 0);
  const ToolRun again = runTool(distanceRun(out("d.nhdr")));
  EXPECT_EQ(again.exitCode, 0) << again.err;
  EXPECT_EQ(listFolder(path("out")), (std::vector<std::string>{"d.nhdr", "d.raw.gz"}));
}

}  // namespace
}  // namespace stvd::testing
