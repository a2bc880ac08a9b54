// `stvd distance` and `stvd info` driven as a user would: through the real
// executable, on the shipped brain and on hand-made files with known answers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "known_field.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

const std::string kDipy = "dti_tensor_dipy5d.nii.gz";
const std::array<int, 3> kCcBody{55, 54, 15};  // CC_body in seeds.tsv

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double percentile(std::vector<double> v, double q) {
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(q * (v.size() - 1))];
}

std::size_t linearIndex(const GridGeometry& g, const std::array<int, 3>& p) {
  return std::size_t(p[0]) + g.size[0] * (std::size_t(p[1]) + g.size[1] * p[2]);
}

class ToolDistance : public ScratchFolderTest {
 protected:
  imaging::ScalarImage distanceFrom(const std::string& input, std::vector<std::string> options,
                                    const std::string& outName, ToolRun* runOut = nullptr) {
    std::vector<std::string> args{"distance", input, "-o", path(outName)};
    args.insert(args.end(), options.begin(), options.end());
    const ToolRun run = runTool(args);
    EXPECT_EQ(run.exitCode, 0) << run.err;
    EXPECT_EQ(run.err, "");
    if (runOut) *runOut = run;
    return imaging::readScalarImage(path(outName));
  }
};

TEST_F(ToolDistance, TheDemoCallWritesADistanceMapOnTheInputGridAndSummarisesItInOneParagraph) {
  ToolRun run;
  const imaging::ScalarImage d =
      distanceFrom(sampleFile(kDipy), {"--seed-voxel", "55,54,15"}, "cc_body_distance.nii.gz", &run);
  const imaging::TensorReadResult input = imaging::readTensorVolume(sampleFile(kDipy));
  EXPECT_EQ(imaging::geometryMismatch(d.geometry, input.volume.geometry), "");
  EXPECT_EQ(d.values[linearIndex(d.geometry, kCcBody)], 0.f);

  // One paragraph on stdout: one line, with what a user needs to know.
  EXPECT_EQ(std::count(run.out.begin(), run.out.end(), '\n'), 1) << run.out;
  for (const std::string& expected : {sampleFile(kDipy), std::string("112 x 112 x 32"), std::string("voxel frame"),
                                     std::string("G = (D/MD)^-1"), std::string("132,892 voxels in the domain"),
                                     std::string("873 were repaired"), std::string("voxel (55, 54, 15)"),
                                     std::string("RAS (6.4, 11.6, 76.3) mm"), std::string("STVD with k = 6 (segment measure)"),
                                     std::string("26-neighbour"), std::string("Reached 132,892"),
                                     std::string("median"), path("cc_body_distance.nii.gz"),
                                     std::string("unreachable voxels = -1")})
    EXPECT_NE(run.out.find(expected), std::string::npos) << "missing '" << expected << "' in: " << run.out;

  // Zero tensors (outside the brain) are unreachable: -1. Every brain voxel
  // is reached, never closer than the metric allows: G = (D/MD)^-1 has no
  // eigenvalue below 1/3, so no path is shorter than |x - seed| / sqrt(3).
  const GridGeometry& g = d.geometry;
  const Vec3d seed = g.indexToPhysicalPoint(kCcBody[0], kCcBody[1], kCcBody[2]);
  std::size_t below = 0;
  for (std::size_t v = 0; v < d.values.size(); ++v) {
    const SymTensor3& t = input.volume.tensors[v];
    const bool zero = t.xx == 0 && t.xy == 0 && t.xz == 0 && t.yy == 0 && t.yz == 0 && t.zz == 0;
    if (zero) {
      EXPECT_EQ(d.values[v], -1.f);
      continue;
    }
    ASSERT_GE(d.values[v], 0.f);
    const std::size_t i = v % g.size[0], j = (v / g.size[0]) % g.size[1], k = v / (g.size[0] * g.size[1]);
    const double euclidean = norm(g.indexToPhysicalPoint(i, j, k) - seed);
    below += d.values[v] < euclidean / std::sqrt(3.0) * (1 - 1e-5);
  }
  EXPECT_EQ(below, 0u) << "voxels closer than the metric's lower bound";
}

TEST_F(ToolDistance, TheSameBrainInThreeFilesGivesTheSameDistanceMap) {
  const imaging::ScalarImage dipy = distanceFrom(sampleFile(kDipy), {"--seed-voxel", "55,54,15", "-q"}, "dipy.nii.gz");
  const imaging::ScalarImage fsl = distanceFrom(sampleFile("dti_tensor_fsl6.nii.gz"),
                                                {"--tensor-order", "fsl", "--seed-voxel", "55,54,15", "-q"}, "fsl.nii.gz");
  const imaging::ScalarImage teem =
      distanceFrom(sampleFile("dti_tensor_teem.nrrd"), {"--seed-voxel", "55,54,15", "-q"}, "teem.nii.gz");

  // The two NIfTI files hold the same tensors: the same map, to rounding.
  double worstNifti = 0.0;
  for (std::size_t v = 0; v < dipy.values.size(); ++v)
    worstNifti = std::max(worstNifti, double(std::abs(fsl.values[v] - dipy.values[v])));
  EXPECT_LE(worstNifti, 1e-4);

  // The NRRD is an independent fit (tensors 0.4 % apart): a few percent.
  std::vector<double> relative;
  std::size_t onlyOne = 0;
  for (std::size_t v = 0; v < dipy.values.size(); ++v) {
    const bool a = dipy.values[v] >= 0, b = teem.values[v] >= 0;
    if (a != b) ++onlyOne;
    if (a && b && dipy.values[v] > 0) relative.push_back(std::abs(teem.values[v] - dipy.values[v]) / dipy.values[v]);
  }
  const double med = median(relative), p95 = percentile(relative, 0.95);
  std::cout << "[ figures  ] CC_body distance maps: DIPY 5D vs FSL-order NIfTI max |difference| " << worstNifti
            << " mm; teem NRRD vs DIPY median relative difference " << 100 * med << " %, 95th percentile "
            << 100 * p95 << " %, " << relative.size() << " voxels compared, " << onlyOne
            << " reached in one map only\n";
  EXPECT_LT(med, 0.03);
  EXPECT_LE(onlyOne, 3u);  // the teem fit's 3 tensors without a positive eigenvalue
}

TEST_F(ToolDistance, ASeedPointInRasOrLpsIsTheSameSeedAsItsVoxel) {
  // CC_body's centre in RAS from the grid itself (seeds.tsv rounds it).
  const imaging::TensorReadResult input = imaging::readTensorVolume(sampleFile(kDipy));
  const Vec3d lps = input.volume.geometry.indexToPhysicalPoint(kCcBody[0], kCcBody[1], kCcBody[2]);
  auto triple = [](double x, double y, double z) {
    std::ostringstream s;
    s.precision(10);
    s << x << "," << y << "," << z;
    return s.str();
  };
  const auto byVoxel = distanceFrom(sampleFile(kDipy), {"--seed-voxel", "55,54,15", "-q"}, "v.nrrd");
  const auto byRas = distanceFrom(sampleFile(kDipy), {"--seed-point", triple(-lps.x, -lps.y, lps.z), "-q"}, "r.nrrd");
  const auto byLps = distanceFrom(sampleFile(kDipy), {"--seed-point", triple(lps.x, lps.y, lps.z), "--lps", "-q"}, "l.nrrd");
  EXPECT_EQ(byRas.values, byVoxel.values);
  EXPECT_EQ(byLps.values, byVoxel.values);
  // The rounded RAS coordinates of seeds.tsv land in the same voxel.
  const auto byTable = distanceFrom(sampleFile(kDipy), {"--seed-point", "6.39,11.57,76.31", "-q"}, "t.nrrd");
  EXPECT_EQ(byTable.values, byVoxel.values);
}

TEST_F(ToolDistance, ExactDistancesThroughTheToolFromAHandWrittenObliqueNrrd) {
  KnownField field;
  const Matrix3 frame = field.measurementFrameLps;
  writeTensorNrrdByHand(path("field.nrrd"), field.geometry, "left-posterior-superior",
                        std::vector<SymTensor3>(field.voxelCount(), field.measurementFrameMetric()), &frame);
  const auto c = field.centre();
  const Vec3d lps = field.geometry.grid().indexToPhysicalPoint(c[0], c[1], c[2]);
  std::ostringstream ras;
  ras.precision(12);
  ras << -lps.x << "," << -lps.y << "," << lps.z;
  for (const std::string method : {"stvd", "dijkstra"}) {
    const auto d = distanceFrom(path("field.nrrd"),
                                {"--tensor-kind", "metric", "--method", method, "--seed-point", ras.str(), "-q"},
                                "d_" + method + ".nii.gz");
    double worst = 0.0;
    for (const auto& p : field.voxelsOnStencilLines()) {
      const double exact = field.exactDistance(c, p);
      worst = std::max(worst, std::abs(d.values[field.linear(p)] - exact) / exact);
    }
    EXPECT_LT(worst, 1e-5) << method;
  }
}

TEST_F(ToolDistance, SeedLabelsMakeEveryNonZeroVoxelASource) {
  const imaging::ScalarImage fa = imaging::readScalarImage(sampleFile("dti_FA.nii.gz"));
  std::vector<float> labels(fa.values.size(), 0.f);
  const std::array<int, 3> left{62, 54, 18}, right{49, 54, 16};  // CC_body_L/R_lateral
  labels[linearIndex(fa.geometry, left)] = 1.f;
  labels[linearIndex(fa.geometry, right)] = 2.f;
  labels[0] = 3.f;  // outside the brain: left out
  imaging::writeScalarImage(path("labels.nii.gz"), fa.geometry, labels);
  ToolRun run;
  const auto d = distanceFrom(sampleFile(kDipy), {"--seeds", path("labels.nii.gz")}, "d.nii.gz", &run);
  EXPECT_EQ(d.values[linearIndex(d.geometry, left)], 0.f);
  EXPECT_EQ(d.values[linearIndex(d.geometry, right)], 0.f);
  EXPECT_GT(d.values[linearIndex(d.geometry, kCcBody)], 0.f);
  EXPECT_NE(run.out.find("1 label voxels outside the domain left out"), std::string::npos) << run.out;
}

TEST_F(ToolDistance, MaxDistanceLeavesFartherVoxelsUnreachable) {
  const auto d = distanceFrom(sampleFile(kDipy), {"--seed-voxel", "55,54,15", "--max-distance", "20", "-q"}, "d.nrrd");
  std::size_t reached = 0, unreachable = 0;
  for (float x : d.values) {
    if (x >= 0) {
      EXPECT_LE(x, 20.f);
      ++reached;
    } else {
      EXPECT_EQ(x, -1.f);
      ++unreachable;
    }
  }
  EXPECT_GT(reached, 100u);
  EXPECT_GT(unreachable, 401408u - 132892u);
}

TEST_F(ToolDistance, UnreachableValueCanBeNan) {
  // NRRD: ITK's NIfTI reader (niftilib) turns non-finite floats into 0 on
  // reading, so a NaN written to NIfTI would come back as a seed's distance.
  const auto d = distanceFrom(sampleFile(kDipy), {"--seed-voxel", "55,54,15", "--unreachable-value", "nan", "-q"},
                              "d.nrrd");
  EXPECT_TRUE(std::isnan(d.values[0])) << d.values[0];
  EXPECT_EQ(d.values[linearIndex(d.geometry, kCcBody)], 0.f);
}

TEST_F(ToolDistance, StatsFileReportsParametersCountsPhasesAndMemory) {
  distanceFrom(sampleFile(kDipy), {"--seed-voxel", "55,54,15", "--method", "dijkstra", "--stencil", "18",
                                   "--stats", path("stats.json"), "-q"},
               "d.nii.gz");
  std::ifstream in(path("stats.json"));
  std::stringstream s;
  s << in.rdbuf();
  const std::string json = s.str();
  for (const std::string key : {"\"method\": \"dijkstra\"", "\"stencil\": \"18\"", "\"tensor_order\": \"lower\"",
                                "\"tensor_frame\": \"voxel\"", "\"domain_vertices\": 132892", "\"relaxed_edges\"",
                                "\"finalized_vertices\": 132892", "\"repaired\": 873", "\"read\"", "\"metric\"",
                                "\"propagate\"", "\"write\"", "\"total\"", "\"peak_memory_bytes\"",
                                "\"ras_mm\"", "\"median\""})
    EXPECT_NE(json.find(key), std::string::npos) << "missing " << key << " in " << json;
  EXPECT_EQ(std::count(json.begin(), json.end(), '{'), std::count(json.begin(), json.end(), '}'));
}

TEST_F(ToolDistance, QuietPrintsNothing) {
  ToolRun run;
  distanceFrom(sampleFile(kDipy), {"--seed-voxel", "55,54,15", "--quiet"}, "d.nii.gz", &run);
  EXPECT_EQ(run.out, "");
}

TEST_F(ToolDistance, MaskAndFaThresholdShrinkTheDomain) {
  ToolRun run;
  const auto d = distanceFrom(sampleFile(kDipy),
                              {"--seed-voxel", "55,54,15", "--mask", sampleFile("dti_mask.nii.gz"), "--fa-threshold",
                               "0.3"},
                              "d.nii.gz", &run);
  const imaging::ScalarImage fa = imaging::readScalarImage(sampleFile("dti_FA.nii.gz"));
  std::size_t lowFaReached = 0;
  for (std::size_t v = 0; v < d.values.size(); ++v) lowFaReached += d.values[v] >= 0 && fa.values[v] < 0.29f;
  EXPECT_EQ(lowFaReached, 0u);
  EXPECT_NE(run.out.find("below the FA threshold"), std::string::npos) << run.out;
}

TEST(ToolHelp, StatesUnitsFramesOrdersDefaultsAndExitCodes) {
  const ToolRun top = runTool({"--help"});
  EXPECT_EQ(top.exitCode, 0);
  EXPECT_NE(top.out.find("distance"), std::string::npos);
  EXPECT_NE(top.out.find("info"), std::string::npos);
  const ToolRun distance = runTool({"distance", "--help"});
  EXPECT_EQ(distance.exitCode, 0);
  for (const std::string expected : {"millimetres", "RAS", "--lps", "xx,xy,yy,xz,yz,zz", "xx,xy,xz,yy,yz,zz",
                                     "xx,yy,zz,xy,xz,yz", "voxel", "world", "default", "-1", "Exit codes",
                                     "lanthier", "--stats", "--max-anisotropy"})
    EXPECT_NE(distance.out.find(expected), std::string::npos) << expected;
  EXPECT_EQ(runTool({"help", "distance"}).out, distance.out);
  const ToolRun info = runTool({"info", "--help"});
  EXPECT_EQ(info.exitCode, 0);
  EXPECT_NE(info.out.find("--tensor-order"), std::string::npos);
}

TEST(ToolInfo, DescribesEachSampleFile) {
  const ToolRun dipy = runTool({"info", sampleFile(kDipy)});
  EXPECT_EQ(dipy.exitCode, 0) << dipy.err;
  for (const std::string expected : {"NIfTI 5D SYMMATRIX", "lower (xx,xy,yy,xz,yz,zz)", "voxel (default",
                                     "112 x 112 x 32", "LAS", "132,892 with a non-zero finite tensor", "lambda1", "FA"})
    EXPECT_NE(dipy.out.find(expected), std::string::npos) << expected << " in " << dipy.out;
  const ToolRun teem = runTool({"info", sampleFile("dti_tensor_teem.nrrd")});
  EXPECT_EQ(teem.exitCode, 0) << teem.err;
  for (const std::string expected : {"3D-masked-symmetric-matrix", "world (default", "Measurement frame",
                                     "852 with a zero or negative smallest eigenvalue", "3 without a positive"})
    EXPECT_NE(teem.out.find(expected), std::string::npos) << expected << " in " << teem.out;
  const ToolRun fsl = runTool({"info", sampleFile("dti_tensor_fsl6.nii.gz"), "--tensor-order", "fsl"});
  EXPECT_EQ(fsl.exitCode, 0) << fsl.err;
  EXPECT_NE(fsl.out.find("fsl (xx,xy,xz,yy,yz,zz), as stated"), std::string::npos) << fsl.out;
}

}  // namespace
}  // namespace stvd::testing
