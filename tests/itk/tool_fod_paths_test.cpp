// `stvd path FOD --fod-basis NAME` and `stvd connectivity FOD --fod-basis
// NAME` (docs/fod.md, "Paths and connectivity") on the synthetic crossing of
// tool_fod_distance_test.cpp (fod_crossing.hpp: bundle 0 along i through
// j = 12, bundle 1 along j through i = 12, 5 voxels wide, 25 x 25 x 3 voxels
// of 1 mm), through the tool. A path stays inside the bundles it follows,
// straight through the crossing along its own; every length it reports is
// the F*-length of the polyline it writes, measured here from the file with
// the FOD metric's table; the formats, the table and the statistics are the
// tensor paths'; bad input is refused in one line with nothing written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "fod_crossing.hpp"
#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/fod_metric.hpp"
#include "stvd/itk/fod_volume_io.hpp"
#include "streamline_reading.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

constexpr int kN = kCrossingSize, kC = kCrossingCentre;

std::string fileText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// The rows of a TSV file as column name -> text.
std::vector<std::map<std::string, std::string>> tsvRows(const std::string& path) {
  std::istringstream in(fileText(path));
  std::string line;
  std::vector<std::string> header;
  std::vector<std::map<std::string, std::string>> rows;
  auto cells = [](const std::string& l) {
    std::vector<std::string> out;
    std::istringstream s(l);
    std::string cell;
    while (std::getline(s, cell, '\t')) out.push_back(cell);
    return out;
  };
  if (std::getline(in, line)) header = cells(line);
  while (std::getline(in, line)) {
    const std::vector<std::string> c = cells(line);
    std::map<std::string, std::string> row;
    for (std::size_t n = 0; n < header.size() && n < c.size(); ++n) row[header[n]] = c[n];
    rows.push_back(row);
  }
  return rows;
}

/// A RAS point of the crossing's grid (index axes = LPS axes, origin 0) as
/// index coordinates.
Vec3d indexOfRas(const Vec3d& ras) { return {-ras.x, -ras.y, ras.z}; }

class ToolFodPaths : public ScratchFolderTest {
 protected:
  void SetUp() override {
    ScratchFolderTest::SetUp();
    writeFodCrossing(path("fod.nii"));
  }

  /// The F*-length of a polyline of voxel centres (index coordinates),
  /// each step measured as the propagation measures an edge: the table of
  /// the FOD metric made here from the file, independently of the tool.
  double fodLength(const std::vector<Vec3d>& indexPoints) {
    if (!metric_) {
      imaging::FodReadOptions read;
      read.basis = "tournier07";
      fod_ = imaging::readFodVolume(path("fod.nii"), read);
      const imaging::FodCostSampler sampler(fod_, imaging::defaultFodSampling(fod_.geometry));
      metric_ = std::make_unique<imaging::FodStencilMetric>(imaging::fodStencilMetric(sampler));
    }
    double length = 0.0;
    for (std::size_t n = 1; n < indexPoints.size(); ++n) {
      const Vec3d a = indexPoints[n - 1], b = indexPoints[n];
      const auto vertex = [](const Vec3d& p) {
        return std::size_t(std::lround(p.x)) + kN * (std::size_t(std::lround(p.y)) + kN * std::size_t(std::lround(p.z)));
      };
      const imaging::FodStencilNorm::EdgeParams e =
          imaging::FodStencilNorm::edgeParams((*metric_)[vertex(a)], (*metric_)[vertex(b)]);
      // Index axes are the LPS axes with 1 mm spacing: the step in LPS millimetres.
      length += imaging::FodStencilNorm::length(e, float(b.x - a.x), float(b.y - a.y), float(b.z - a.z));
    }
    return length;
  }

  /// A refused run: exit code `code`, one line on stderr holding `words`, nothing written.
  void expectRefused(const std::vector<std::string>& arguments, int code, const std::string& words) const {
    const ToolRun r = runTool(arguments);
    EXPECT_EQ(r.exitCode, code) << r.err;
    EXPECT_NE(r.err.find(words), std::string::npos) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    for (const char* name : {"refused.vtk", "refused.tsv", "refused.json", "refused_table.tsv"})
      EXPECT_FALSE(std::filesystem::exists(path(name))) << name;
  }

  imaging::FodField fod_;
  std::unique_ptr<imaging::FodStencilMetric> metric_;
};

TEST_F(ToolFodPaths, APathFollowsItsOwnBundleThroughTheCrossingAtItsFStarLength) {
  // From one end of bundle 0 to its far end, and to the far end of bundle 1.
  const ToolRun r = runTool({"path", path("fod.nii"), "-q", "--fod-basis", "tournier07", "--seed-voxel", "0,12,1",
                             "--target-voxel", "24,12,1", "--target-voxel", "12,24,1", "-o", path("p.vtk"), "--stats",
                             path("p.json")});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const LoadedStreamlines lines = loadLegacyVtk(path("p.vtk"));
  ASSERT_TRUE(lines.error.empty()) << lines.error;
  ASSERT_EQ(lines.lines.size(), 2u);
  const std::vector<std::map<std::string, std::string>> rows = tsvRows(path("p.tsv"));
  ASSERT_EQ(rows.size(), 2u);

  for (int n = 0; n < 2; ++n) {
    std::vector<Vec3d> points;
    for (const Vec3d& ras : lines.lines[n]) points.push_back(indexOfRas(ras));
    ASSERT_GE(points.size(), 2u);
    // The seed end first, the target last.
    EXPECT_NEAR(points.front().x, 0.0, 1e-4);
    EXPECT_NEAR(points.front().y, kC, 1e-4);
    EXPECT_NEAR(points.back().x, n == 0 ? kN - 1 : kC, 1e-4);
    EXPECT_NEAR(points.back().y, n == 0 ? kC : kN - 1, 1e-4);
    for (const Vec3d& p : points) {
      EXPECT_NEAR(p.z, 1.0, 1e-4);
      const double off0 = distanceFromCrossingAxis(0, 90, p.x, p.y), off1 = distanceFromCrossingAxis(1, 90, p.x, p.y);
      if (n == 0)  // on its own bundle's axis, straight through the crossing
        EXPECT_LT(off0, 1e-4) << "path " << n << " at " << p.x << "," << p.y;
      else  // along bundle 0, then along bundle 1: never outside both
        EXPECT_LE(std::min(off0, off1), kCrossingHalfWidth + 1e-4) << "path " << n << " at " << p.x << "," << p.y;
    }
    const double geodesic = std::stod(rows[n].at("geodesic_mm"));
    const double metricLength = std::stod(rows[n].at("metric_length_mm"));
    const double measured = fodLength(points);
    // The reported length is the F*-length of the polyline written.
    EXPECT_NEAR(measured, geodesic, 1e-4 * geodesic) << "path " << n;
    EXPECT_NEAR(metricLength, geodesic, 1e-4 * geodesic) << "path " << n;
    EXPECT_NEAR(lines.perLine.at("geodesic_mm").at(n), geodesic, 1e-4 * geodesic);
    // Along bundle 0 at 1 per mm: 24 mm; to bundle 1's far end, two legs of 12.
    EXPECT_NEAR(geodesic, 24.0, n == 0 ? 24e-3 : 0.02 * 24.0);
    EXPECT_EQ(rows[n].at("refine_iterations"), "0");
    EXPECT_EQ(rows[n].at("gradient_steps"), "0");
    EXPECT_EQ(rows[n].at("mean_fa"), "n/a");
    EXPECT_EQ(std::stoul(rows[n].at("discrete_points")), points.size());
  }
  const std::string stats = fileText(path("p.json"));
  for (const char* member : {"\"command\": \"path\"", "\"metric\": \"fod\"", "\"fod_basis\": \"tournier07\"",
                             "\"fod_lmax\": 8", "\"method\": \"dijkstra\"", "\"fod_precomputation\": {",
                             "\"path_count\": 2"})
    EXPECT_NE(stats.find(member), std::string::npos) << member << "\n" << stats;
}

TEST_F(ToolFodPaths, PathsAreWrittenInEveryFormatAndTheSameOnOneAndTwoThreads) {
  for (const char* threads : {"1", "2"})
    for (const char* extension : {".tck", ".trk"}) {
      const std::string out = path(std::string("p") + threads + extension);
      const ToolRun r = runTool({"path", path("fod.nii"), "-q", "--fod-basis", "tournier07", "--threads", threads,
                                 "--seed-voxel", "0,12,1", "--target-voxel", "24,12,1", "-o", out});
      ASSERT_EQ(r.exitCode, 0) << r.err;
    }
  EXPECT_EQ(fileText(path("p1.tck")), fileText(path("p2.tck")));
  EXPECT_EQ(fileText(path("p1.trk")), fileText(path("p2.trk")));
  for (const char* name : {"p1.tck", "p1.trk"}) {
    const LoadedStreamlines loaded = loadWithNibabel(path(name));
    ASSERT_TRUE(loaded.error.empty()) << name << ": " << loaded.error;
    ASSERT_EQ(loaded.lines.size(), 1u) << name;
    ASSERT_EQ(loaded.lines[0].size(), 25u) << name;  // the 25 voxel centres of bundle 0's axis
    for (int n = 0; n < 25; ++n) {
      const Vec3d p = indexOfRas(loaded.lines[0][n]);
      EXPECT_NEAR(p.x, n, 1e-4) << name;
      EXPECT_NEAR(p.y, kC, 1e-4) << name;
    }
  }
  const LoadedStreamlines trk = loadWithNibabel(path("p1.trk"));
  EXPECT_NEAR(trk.perLine.at("geodesic_mm").at(0), 24.0, 24e-3);
}

TEST_F(ToolFodPaths, BadPathInputsAreRefusedInOneLineWithNothingWritten) {
  const std::string fod = path("fod.nii"), out = path("refused.vtk");
  const std::vector<std::string> ends{"--seed-voxel", "0,12,1", "--target-voxel", "24,12,1", "-o", out};
  auto with = [&](std::vector<std::string> a) {
    a.insert(a.begin(), {"path", fod});
    a.insert(a.end(), ends.begin(), ends.end());
    return a;
  };
  expectRefused(with({"--fod-basis", "tournier07", "--step", "0.5"}), 2, "not traced or refined");
  expectRefused(with({"--fod-basis", "tournier07", "--no-refine"}), 2, "not traced or refined");
  expectRefused(with({"--fod-basis", "tournier07", "--method", "stvd"}), 2, "use --method dijkstra");
  expectRefused(with({"--fod-basis", "tournier07", "--tensor-order", "fsl"}), 2, "applies to tensor images");
  expectRefused(with({"--fod-basis", "tournier08"}), 2, "--fod-basis");
  expectRefused(with({"--fod-floor", "0.2"}), 2, "--fod-floor applies to FOD images");
  expectRefused(with({"--threads", "2"}), 2, "--threads applies to FOD images");
  expectRefused({"path", fod, "--fod-basis", "tournier07", "--seed-voxel", "0,12,1", "--target-voxel", "30,12,1", "-o",
                 out},
                4, "outside the image");
  // A mask of bundle 0: bundle 1's far end is not reachable.
  HandGeometry g;
  g.size = {kN, kN, 3};
  std::vector<float> mask(std::size_t(kN) * kN * 3, 0.f);
  for (int k = 0; k < 3; ++k)
    for (int j = kC - kCrossingHalfWidth; j <= kC + kCrossingHalfWidth; ++j)
      for (int i = 0; i < kN; ++i) mask[i + kN * (j + kN * k)] = 1.f;
  writeScalarNiftiByHand(path("mask.nii"), g, mask);
  expectRefused({"path", fod, "--fod-basis", "tournier07", "--mask", path("mask.nii"), "--seed-voxel", "0,12,1",
                 "--target-voxel", "12,24,1", "-o", out},
                4, "outside the mask");
}

class ToolFodConnectivity : public ToolFodPaths {
 protected:
  void SetUp() override {
    ToolFodPaths::SetUp();
    // Regions at the four ends of the bundles: 1 and 2 bundle 0's (i = 0, 24),
    // 3 and 4 bundle 1's (j = 0, 24), each the middle voxel of its end.
    HandGeometry g;
    g.size = {kN, kN, 3};
    std::vector<float> labels(std::size_t(kN) * kN * 3, 0.f);
    const auto at = [](int i, int j) { return std::size_t(i) + kN * (std::size_t(j) + kN * 1); };
    labels[at(0, kC)] = 1;
    labels[at(kN - 1, kC)] = 2;
    labels[at(kC, 0)] = 3;
    labels[at(kC, kN - 1)] = 4;
    writeScalarNiftiByHand(path("ends.nii"), g, labels);
  }
};

TEST_F(ToolFodConnectivity, EachEndIsNoFurtherFromItsOwnFarEndThanFromTheOtherBundlesEnds) {
  const ToolRun r = runTool({"connectivity", path("fod.nii"), "-q", "--fod-basis", "tournier07", "--labels",
                             path("ends.nii"), "-o", path("c.tsv"), "--matrix", path("c.csv"), "--stats",
                             path("c.json")});
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const std::vector<std::map<std::string, std::string>> rows = tsvRows(path("c.tsv"));
  ASSERT_EQ(rows.size(), 12u);
  std::map<std::pair<int, int>, std::map<std::string, std::string>> pair;
  for (const auto& row : rows) pair[{std::stoi(row.at("region_a")), std::stoi(row.at("region_b"))}] = row;
  const auto own = [](int a) { return a == 1 ? 2 : a == 2 ? 1 : a == 3 ? 4 : 3; };
  for (int a = 1; a <= 4; ++a) {
    const double ownFarEnd = std::stod(pair.at({a, own(a)}).at("geodesic_mm"));
    // Straight through the crossing along its own bundle, at 1 per mm.
    EXPECT_NEAR(ownFarEnd, 24.0, 24e-3) << a;
    EXPECT_NEAR(std::stod(pair.at({a, own(a)}).at("path_mm")), 24.0, 1e-3) << a;
    for (int b = 1; b <= 4; ++b) {
      if (b == a || b == own(a)) continue;
      const auto& row = pair.at({a, b});
      const double other = std::stod(row.at("geodesic_mm"));
      // The straight line is shorter (12 sqrt 2 = 17 mm), but the metric
      // leads along one bundle and then the other: 12 + 12 mm. The turn in
      // the crossing is free under a convex norm (F* holds both lobes
      // there), so the other bundle's ends tie with the own far end at best.
      EXPECT_NEAR(std::stod(row.at("straight_mm")), 12.0 * std::sqrt(2.0), 1e-3) << a << "->" << b;
      EXPECT_GE(other, ownFarEnd - 0.02 * 24.0) << a << "->" << b;
      EXPECT_NEAR(other, 24.0, 0.02 * 24.0) << a << "->" << b;
      // Not the straight line: along the bundles, cutting the corner
      // inside the crossing (F* there holds both fibres), and never longer
      // than its F*-length (F* >= |v|: the best direction costs 1 per mm).
      EXPECT_GT(std::stod(row.at("path_mm")), 20.0) << a << "->" << b;
      EXPECT_LE(std::stod(row.at("path_mm")), other + 1e-3) << a << "->" << b;
    }
  }
  EXPECT_FALSE(fileText(path("c.csv")).empty());
  const std::string stats = fileText(path("c.json"));
  for (const char* member : {"\"command\": \"connectivity\"", "\"metric\": \"fod\"", "\"fod_precomputation\": {",
                             "\"regions\": {\"count\": 4"})
    EXPECT_NE(stats.find(member), std::string::npos) << member << "\n" << stats;
}

TEST_F(ToolFodConnectivity, TheTableIsTheSameOnOneAndTwoThreadsAndBadInputIsRefused) {
  for (const char* threads : {"1", "2"})
    ASSERT_EQ(runTool({"connectivity", path("fod.nii"), "-q", "--fod-basis", "tournier07", "--threads", threads,
                       "--labels", path("ends.nii"), "-o", path(std::string("c") + threads + ".tsv")})
                  .exitCode,
              0);
  EXPECT_EQ(fileText(path("c1.tsv")), fileText(path("c2.tsv")));
  const std::string fod = path("fod.nii"), out = path("refused_table.tsv");
  expectRefused({"connectivity", fod, "--fod-basis", "tournier07", "--method", "stvd", "--labels", path("ends.nii"),
                 "-o", out},
                2, "use --method dijkstra");
  expectRefused({"connectivity", fod, "--fod-basis", "tournier07", "--fa-threshold", "0.2", "--labels",
                 path("ends.nii"), "-o", out},
                2, "applies to tensor images");
  expectRefused({"connectivity", fod, "--fod-power", "2", "--labels", path("ends.nii"), "-o", out}, 2,
                "--fod-power applies to FOD images");
  // Labels on another grid.
  HandGeometry g;
  g.size = {5, 5, 3};
  writeScalarNiftiByHand(path("small.nii"), g, std::vector<float>(75, 1.f));
  expectRefused({"connectivity", fod, "--fod-basis", "tournier07", "--labels", path("small.nii"), "-o", out}, 3,
                "small.nii");
}

}  // namespace
}  // namespace stvd::testing
