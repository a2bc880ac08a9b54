// The same input and options give the same bytes: every output of every
// command, run after run, and for `stvd connectivity` whatever the number of
// threads. The statistics file (--stats) is the same except for the fields
// that measure the run (docs/reliability.md lists them).
#include <gtest/gtest.h>

#include <filesystem>
#include <regex>

#include "known_field.hpp"
#include "small_inputs.hpp"

namespace stvd::testing {
namespace {

namespace fs = std::filesystem;

class ToolDeterminism : public SmallInputsTest {
 protected:
  /// What `arguments` write into out/ (emptied first), the measured fields
  /// of statistics files (*.json) blanked.
  FolderSnapshot outputsOf(const std::vector<std::string>& arguments) {
    for (const auto& entry : fs::directory_iterator(path("out"))) fs::remove_all(entry.path());
    const ToolRun run = runTool(arguments);
    EXPECT_EQ(run.exitCode, 0) << run.err;
    FolderSnapshot files = snapshot(path("out"));
    for (auto& [name, bytes] : files)
      if (name.size() > 5 && name.compare(name.size() - 5, 5, ".json") == 0) bytes = withoutMeasurements(bytes);
    EXPECT_FALSE(files.empty());
    return files;
  }
  static std::string withoutMeasurements(const std::string& json) {
    static const std::regex measured(
        R"re(("seconds"|"cpu_seconds"|"peak_memory_bytes"|"resident_bytes"|"available_bytes"|"limited_by"): (\{[^}]*\}|[0-9]+|"[^"]*"|null))re");
    return std::regex_replace(json, measured, "$1: (measured)");
  }
  void expectSameBytesTwice(const std::vector<std::string>& arguments) {
    const FolderSnapshot first = outputsOf(arguments);
    EXPECT_TRUE(outputsOf(arguments) == first) << arguments[1] << " -o " << first.begin()->first;
  }
};

TEST_F(ToolDeterminism, DistanceMapsAndStatisticsInEveryFormat) {
  std::vector<std::string> names{"d.nii", "d.nii.gz", "d.nrrd", "d.nhdr"};
  if (withVdb()) names.push_back("d.vdb");
  for (const std::string& name : names) expectSameBytesTwice(distanceRun(out(name), out("d.json")));
  std::vector<std::string> lanthier = distanceRun(out("l.nii"), out("l.json"));
  lanthier.insert(lanthier.end(), {"--method", "lanthier", "--steiner", "2"});
  expectSameBytesTwice(lanthier);
}

TEST_F(ToolDeterminism, CompressedOutputsCarryNoTimeStamp) {
  // Two runs within one second would agree even with a time stamp in the
  // gzip header (bytes 4 to 7, seconds since 1970); it must be zero.
  FolderSnapshot files;
  for (const std::string name : {"d.nii.gz", "d.nrrd", "d.nhdr"}) files.merge(outputsOf(distanceRun(out(name))));
  const std::string nrrd = files.at("d.nrrd");
  const std::size_t data = nrrd.find("\n\n") + 2;
  for (const std::string& gzip : {files.at("d.nii.gz"), files.at("d.raw.gz"), nrrd.substr(data)}) {
    ASSERT_GE(gzip.size(), 10u);
    EXPECT_EQ(gzip.substr(0, 2), "\x1f\x8b");
    EXPECT_EQ(gzip.substr(4, 4), std::string(4, '\0'));
  }
}

TEST_F(ToolDeterminism, MrtrixImagesAndTheirCompressedStream) {
  for (const std::string name : {"d.mif", "d.mif.gz"}) expectSameBytesTwice(distanceRun(out(name), out("d.json")));
  std::vector<std::string> fromMrtrix = distanceRun(out("m.mif"));
  fromMrtrix[1] = in("t.mih");
  expectSameBytesTwice(fromMrtrix);
  const std::string gzip = outputsOf(distanceRun(out("d.mif.gz"))).at("d.mif.gz");
  ASSERT_GE(gzip.size(), 10u);
  EXPECT_EQ(gzip.substr(0, 2), "\x1f\x8b");
  EXPECT_EQ(gzip.substr(4, 4), std::string(4, '\0'));  // no time stamp
}

TEST_F(ToolDeterminism, TheStatisticsDifferOnlyInWhatTheyMeasure) {
  const FolderSnapshot files = outputsOf(distanceRun(out("d.nii"), out("d.json")));
  const std::string& json = files.at("d.json");
  EXPECT_NE(json.find("\"seconds\": (measured)"), std::string::npos) << json;
  EXPECT_NE(json.find("\"peak_memory_bytes\": (measured)"), std::string::npos) << json;
  EXPECT_NE(json.find("\"resident_bytes\": (measured), \"available_bytes\": (measured), \"limited_by\": (measured)"),
            std::string::npos)
      << json;
}

TEST_F(ToolDeterminism, PathsAndTheirTables) {
  for (const std::string name : {"p.trk", "p.tck", "p.vtk"}) expectSameBytesTwice(pathRun(out(name), out("p.tsv")));
}

TEST_F(ToolDeterminism, ConnectivityDoesNotDependOnTheNumberOfThreads) {
  // Six regions under a constant metric, where many paths tie: the order in
  // which threads finish must not matter.
  const KnownField field;
  std::vector<float> labels(field.voxelCount(), 0.f);
  const std::array<int, 3> centres[6] = {{1, 1, 1}, {9, 1, 1}, {1, 7, 1}, {9, 7, 5}, {5, 4, 3}, {2, 6, 5}};
  for (int r = 0; r < 6; ++r) labels[field.linear(centres[r])] = static_cast<float>(10 * (r + 1));
  writeScalarNiftiByHand(in("regions.nii"), field.geometry, labels);
  std::vector<std::string> arguments{"connectivity", in("t.nii"), "--tensor-kind", "metric", "--labels",
                                     in("regions.nii"), "-o", out("c.tsv"), "-q", "--threads", "1"};
  const FolderSnapshot one = outputsOf(arguments);
  for (const std::string threads : {"2", "3", "6", "1"}) {
    arguments.back() = threads;
    EXPECT_TRUE(outputsOf(arguments) == one) << threads << " threads";
  }
}

TEST_F(ToolDeterminism, ConnectivityMatricesDoNotDependOnTheNumberOfThreads) {
  std::vector<std::string> arguments = connectivityRun(out("c.tsv"));
  arguments.insert(arguments.end(), {"--matrix", out("d.csv"), "--matrix-index", out("i.csv"), "--threads", "1"});
  const FolderSnapshot one = outputsOf(arguments);
  EXPECT_EQ(one.size(), 3u);
  arguments.back() = "2";
  EXPECT_TRUE(outputsOf(arguments) == one);
}

TEST_F(ToolDeterminism, TetMeshDistances) {
  for (const std::string name : {"m.vtk", "m.vtu", "m.csv"}) expectSameBytesTwice(tetMeshRun(out(name)));
  std::vector<std::string> resampled = tetMeshRun(out("m.nii.gz"));
  resampled.insert(resampled.end(), {"--reference", in("mask.nii")});
  expectSameBytesTwice(resampled);
}

TEST_F(ToolDeterminism, SurfaceDistances) {
  for (const std::string name : {"s.ply", "s.vtk", "s.csv"}) expectSameBytesTwice(surfaceRun(out(name)));
}

TEST_F(ToolDeterminism, SurfaceStatisticsAndStlInput) {
  std::vector<std::string> run = surfaceRun(out("s.ply"));
  run.insert(run.end(), {"--stats", out("s.json"), "--seed-point", "1.5,1.5,0", "--seed-at", "point"});
  expectSameBytesTwice(run);
  expectSameBytesTwice({"distance", in("tetra.stl"), "--seed-vertex", "0", "-o", out("t.ply"), "--stats",
                        out("t.json"), "-q"});
}

TEST_F(ToolDeterminism, TetrahedralizedMeshes) {
  if (!withTetrahedralize()) GTEST_SKIP() << "built without TetGen";
  expectSameBytesTwice(tetrahedralizeRun(out("box")));
}

}  // namespace
}  // namespace stvd::testing
