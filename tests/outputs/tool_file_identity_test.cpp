// No command writes over one of its inputs, however the two are spelled:
// before anything is read or computed, every output is compared with every
// input (and with the files an input brings: a NRRD or MRtrix .mih
// header's data file, a mesh's .ele and .face files, a .poly surface's
// points) by what file it is; the QC report (--report) too.
// A match is one line naming both roles, exit code 2, and no file written
// or changed.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "known_field.hpp"
#include "small_inputs.hpp"

namespace stvd::testing {
namespace {

namespace fs = std::filesystem;

constexpr int kUsage = 2;

class ToolFileIdentity : public SmallInputsTest {
 protected:
  /// Runs `arguments` and expects the refusal: exit code 2, one stderr
  /// line naming `output` and saying "the <outputRole> is the <inputRole>",
  /// and not one byte changed in the scratch folder.
  void expectRefused(const std::vector<std::string>& arguments, const std::string& output,
                     const std::string& outputRole, const std::string& inputRole) {
    const FolderSnapshot before = snapshot(path(""));
    const ToolRun run = runTool(arguments);
    EXPECT_EQ(run.exitCode, kUsage) << run.err;
    EXPECT_EQ(run.out, "");
    ASSERT_FALSE(run.err.empty());
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << "more than one line: " << run.err;
    EXPECT_NE(run.err.find(output + ": the " + outputRole + " is the " + inputRole), std::string::npos)
        << run.err;
    EXPECT_TRUE(snapshot(path("")) == before) << "the run changed a file";
  }
};

TEST_F(ToolFileIdentity, TheDistanceMapIsNeverTheTensorInput) {
  expectRefused({"distance", in("t.nii"), "--tensor-kind", "metric", "--seed-voxel", "5,4,3", "-o", in("t.nii")},
                in("t.nii"), "distance map", "tensor input");
}

TEST_F(ToolFileIdentity, SpellingThroughDotDotOrDotDoesNotHideTheInput) {
  const std::string viaDotDot = path("out/../in/t.nii"), viaDot = path("in/./t.nii");
  expectRefused(distanceRun(viaDotDot), viaDotDot, "distance map", "tensor input");
  expectRefused(distanceRun(viaDot), viaDot, "distance map", "tensor input");
}

TEST_F(ToolFileIdentity, ASymbolicLinkDoesNotHideTheInput) {
  // The output is a link to the input, and the input is given through a link.
  fs::create_symlink(in("t.nii"), out("link.nii"));
  expectRefused(distanceRun(out("link.nii")), out("link.nii"), "distance map", "tensor input");
  std::vector<std::string> throughLink = distanceRun(in("t.nii"));
  throughLink[1] = out("link.nii");
  expectRefused(throughLink, in("t.nii"), "distance map", "tensor input");
}

TEST_F(ToolFileIdentity, TheDistanceMapIsNeverTheMaskOrTheSeedLabels) {
  expectRefused(distanceRun(in("mask.nii")), in("mask.nii"), "distance map", "mask");
  std::vector<std::string> seeds{"distance", in("t.nii"), "--tensor-kind", "metric", "--seeds", in("labels.nii"),
                                 "-o", in("labels.nii")};
  expectRefused(seeds, in("labels.nii"), "distance map", "seed labels");
}

TEST_F(ToolFileIdentity, TheStatisticsFileIsNeverAnInputNorTheDistanceMap) {
  expectRefused(distanceRun(out("d.nii"), in("t.nii")), in("t.nii"), "statistics file", "tensor input");
  expectRefused(distanceRun(out("d.nii"), path("out/./d.nii")), path("out/./d.nii"), "statistics file",
                "distance map");
}

TEST_F(ToolFileIdentity, AHeaderOutputsDataFileIsNeverTheDataFileOfAnInput) {
  // A detached NRRD header whose data file is "d.raw.gz": writing "d.nhdr"
  // next to it would put the distance map's data over the tensors'.
  const KnownField field;
  writeTensorNrrdByHand(in("attached.nrrd"), field.geometry, "left-posterior-superior",
                        std::vector<SymTensor3>(field.voxelCount(), field.lpsMetric()), nullptr);
  std::ifstream attached(in("attached.nrrd"), std::ios::binary);
  std::string header, line;
  while (std::getline(attached, line) && !line.empty()) header += line + "\n";
  std::ofstream(in("t.nhdr")) << header << "data file: d.raw.gz\n\n";
  std::ofstream(in("d.raw.gz"), std::ios::binary) << attached.rdbuf();
  fs::remove(in("attached.nrrd"));
  std::vector<std::string> run{"distance", in("t.nhdr"), "--tensor-kind", "metric", "--seed-voxel", "5,4,3",
                               "-o", in("d.nhdr")};
  expectRefused(run, in("d.raw.gz"), "data file of the distance map", "data file of the tensor input");
  // And a statistics file named like the data file.
  run.back() = out("d.nhdr");
  run.insert(run.end(), {"--stats", in("d.raw.gz")});
  expectRefused(run, in("d.raw.gz"), "statistics file", "data file of the tensor input");
}

TEST_F(ToolFileIdentity, PathOutputsAreNeverInputsNorEachOther) {
  expectRefused(pathRun(out("p.trk"), in("labels.nii")), in("labels.nii"), "path table", "target labels");
  expectRefused(pathRun(out("p.trk"), path("out/./p.trk")), path("out/./p.trk"), "path table", "paths file");
}

TEST_F(ToolFileIdentity, TheConnectivityTableIsNeverTheLabelImage) {
  expectRefused(connectivityRun(in("labels.nii")), in("labels.nii"), "connectivity table", "label image");
}

TEST_F(ToolFileIdentity, MrtrixImagesAndTheDataFileOfAMihHeaderAreInputsToo) {
  expectRefused({"distance", in("t.mif"), "--tensor-kind", "metric", "--seed-voxel", "5,4,3", "-o",
                 path("in/./t.mif")},
                path("in/./t.mif"), "distance map", "tensor input");
  // A .mih header's data file comes along with it.
  expectRefused({"distance", in("t.mih"), "--tensor-kind", "metric", "--seed-voxel", "5,4,3", "-o", out("d.mif"),
                 "--stats", in("t.dat")},
                in("t.dat"), "statistics file", "data file of the tensor input");
  expectRefused({"distance", in("t.nii"), "--tensor-kind", "metric", "--seed-voxel", "5,4,3", "--mask", in("t.mih"),
                 "-o", out("d.mif"), "--stats", path("out/../in/t.dat")},
                path("out/../in/t.dat"), "statistics file", "data file of the mask");
}

TEST_F(ToolFileIdentity, ConnectivityMatricesAreNeverInputsNorTheTable) {
  std::vector<std::string> run = connectivityRun(out("c.tsv"));
  run.insert(run.end(), {"--matrix", in("labels.nii")});
  expectRefused(run, in("labels.nii"), "distance matrix", "label image");
  run = connectivityRun(out("c.tsv"));
  run.insert(run.end(), {"--matrix", out("d.csv"), "--matrix-index", path("out/./c.tsv")});
  expectRefused(run, path("out/./c.tsv"), "connectivity-index matrix", "connectivity table");
}

TEST_F(ToolFileIdentity, TheQcReportIsNeverAnInputNorAnotherOutput) {
  // --report goes through the same check as every other output, before
  // anything is computed (and before Python is asked whether it can draw).
  fs::create_symlink(in("t.nii"), out("link.html"));
  std::vector<std::string> run = distanceRun(out("d.nii"));
  run.insert(run.end(), {"--report", out("link.html")});
  expectRefused(run, out("link.html"), "QC report", "tensor input");
  run = distanceRun(out("d.nii"), out("s.json"));
  run.insert(run.end(), {"--report", path("out/./s.json")});
  expectRefused(run, path("out/./s.json"), "QC report", "statistics file");
  run = pathRun(out("p.trk"), out("p.tsv"));
  run.insert(run.end(), {"--report", path("out/../out/p.tsv")});
  expectRefused(run, path("out/../out/p.tsv"), "QC report", "path table");
  run = connectivityRun(out("c.tsv"));
  run.insert(run.end(), {"--report", path("out/../in/labels.nii")});
  expectRefused(run, path("out/../in/labels.nii"), "QC report", "label image");
}

TEST_F(ToolFileIdentity, TetMeshOutputsAreNeverTheTensorOrReferenceImage) {
  expectRefused({"distance", in("cube.node"), "--seed-vertex", "1", "--reference", in("mask.nii"), "-o",
                 in("mask.nii")},
                in("mask.nii"), "distance output", "reference image");
  expectRefused({"distance", in("cube.node"), "--seed-vertex", "1", "--tensors", in("t.nii"), "--tensor-kind",
                 "metric", "--reference", in("mask.nii"), "-o", in("t.nii")},
                in("t.nii"), "distance output", "tensor image");
}

TEST_F(ToolFileIdentity, SurfaceOutputsAreNeverTheMeshOrTheMetricFile) {
  std::ofstream(in("field.csv")) << "1 0 0\n";
  expectRefused({"distance", in("square.ply"), "--seed-vertex", "0", "-o", path("in/../in/square.ply")},
                path("in/../in/square.ply"), "distance output", "surface mesh");
  expectRefused({"distance", in("square.ply"), "--seed-vertex", "0", "--metric", "field:" + in("field.csv"),
                 "--anisotropy", "2", "-o", in("field.csv")},
                in("field.csv"), "distance output", "metric file");
}

TEST_F(ToolFileIdentity, SurfaceStatisticsAreNeverTheMeshNorTheDistanceOutput) {
  std::vector<std::string> run = surfaceRun(out("s.ply"));
  run.insert(run.end(), {"--stats", in("square.ply")});
  expectRefused(run, in("square.ply"), "statistics file", "surface mesh");
  expectRefused({"distance", in("tetra.stl"), "--seed-vertex", "0", "-o", out("s.csv"), "--stats", in("tetra.stl")},
                in("tetra.stl"), "statistics file", "surface mesh");
  run = surfaceRun(out("s.csv"));
  run.insert(run.end(), {"--stats", path("out/./s.csv")});
  expectRefused(run, path("out/./s.csv"), "statistics file", "distance output");
}

TEST_F(ToolFileIdentity, TetrahedralizeNeverWritesOverThePointsOfAPolySurface) {
  if (!withTetrahedralize()) GTEST_SKIP() << "built without TetGen";
  // A .poly file with no points of its own takes them from the .node file
  // of the same name, which "-o box" would replace.
  std::ofstream(in("box.node")) << "8 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 1 1 0\n5 0 0 1\n6 1 0 1\n7 0 1 1\n8 1 1 1\n";
  std::ofstream(in("box.poly")) << "0 3 0 0\n6 0\n1\n4 1 3 4 2\n1\n4 5 6 8 7\n1\n4 1 2 6 5\n1\n4 3 7 8 4\n"
                                   "1\n4 1 5 7 3\n1\n4 2 4 8 6\n0\n0\n";
  expectRefused({"tetrahedralize", in("box.poly"), "-o", in("box")}, in("box.node"), ".node file of the output mesh",
                "points file of the input surface");
}

TEST_F(ToolFileIdentity, DistinctFilesStillWork) {
  const ToolRun run = runTool(distanceRun(out("d.nii"), out("d.json")));
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_EQ(listFolder(path("out")), (std::vector<std::string>{"d.json", "d.nii"}));
}

}  // namespace
}  // namespace stvd::testing
