// `stvd path` driven through the real executable on the shipped brain: the
// streamline files as nibabel reads them (RAS millimetres checked against
// the world points of seeds.tsv), the anatomy of two known tracts, label
// targets, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "stvd/itk/scalar_image_io.hpp"
#include "streamline_reading.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

const std::string kDipy = "dti_tensor_dipy5d.nii.gz";

/// A row of sample_data/dti_philips_biobank/seeds.tsv.
struct NamedVoxel {
  std::array<int, 3> index;
  Vec3d ras;  // the file's x_ras_mm, y_ras_mm, z_ras_mm (2 decimals)
};

std::map<std::string, NamedVoxel> seedTable() {
  std::ifstream in(sampleFile("seeds.tsv"));
  std::string line;
  std::getline(in, line);  // header
  std::map<std::string, NamedVoxel> table;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string name;
    NamedVoxel v;
    row >> name >> v.index[0] >> v.index[1] >> v.index[2] >> v.ras.x >> v.ras.y >> v.ras.z;
    table[name] = v;
  }
  return table;
}

std::string triple(const std::array<int, 3>& v) {
  return std::to_string(v[0]) + "," + std::to_string(v[1]) + "," + std::to_string(v[2]);
}

// seeds.tsv gives RAS to 2 decimals: 0.005 mm rounding, plus float32 storage.
constexpr double kSeedTableTolerance = 0.006;

void expectNear(const Vec3d& a, const Vec3d& b, double tolerance, const std::string& what) {
  EXPECT_NEAR(a.x, b.x, tolerance) << what;
  EXPECT_NEAR(a.y, b.y, tolerance) << what;
  EXPECT_NEAR(a.z, b.z, tolerance) << what;
}

class ToolPath : public ScratchFolderTest {
 protected:
  ToolRun pathRun(const std::vector<std::string>& options) {
    std::vector<std::string> args{"path", sampleFile(kDipy)};
    args.insert(args.end(), options.begin(), options.end());
    return runTool(args);
  }
  /// RAS point -> continuous voxel index of the sample's grid.
  Vec3d rasToIndex(const Vec3d& ras) {
    if (!geometryRead_) {
      geometry_ = imaging::readScalarImage(sampleFile("dti_FA.nii.gz")).geometry;
      geometryRead_ = true;
    }
    return geometry_.physicalPointToIndex({-ras.x, -ras.y, ras.z});
  }

 private:
  GridGeometry geometry_;
  bool geometryRead_ = false;
};

TEST_F(ToolPath, EachStreamlineFormatLandsOnTheAnatomyInNibabel) {
  const auto seeds = seedTable();
  const NamedVoxel from = seeds.at("CC_body_R_lateral"), to = seeds.at("CC_body_L_lateral"),
                   body = seeds.at("CC_body");
  std::vector<LoadedStreamlines> loaded;
  for (const std::string format : {"tck", "trk", "vtk"}) {
    const ToolRun run = pathRun({"--seed-voxel", triple(from.index), "--target-voxel", triple(to.index),
                                 "--target-voxel", triple(body.index), "-o", path("cc." + format)});
    ASSERT_EQ(run.exitCode, 0) << run.err;
    loaded.push_back(format == "vtk" ? loadLegacyVtk(path("cc.vtk")) : loadWithNibabel(path("cc." + format)));
    const LoadedStreamlines& l = loaded.back();
    ASSERT_EQ(l.error, "") << format;
    ASSERT_EQ(l.lines.size(), 2u) << format;
    // Every path runs from the seed (first point) to its target (last).
    for (std::size_t n = 0; n < 2; ++n) {
      expectNear(l.lines[n].front(), from.ras, kSeedTableTolerance, format + ": seed end");
      expectNear(l.lines[n].back(), n == 0 ? to.ras : body.ras, kSeedTableTolerance, format + ": target end");
    }
    const auto rows = readTsv(path("cc.tsv"));
    ASSERT_EQ(rows.size(), 2u);
    if (format != "tck") {
      for (std::size_t n = 0; n < 2; ++n) {
        EXPECT_NEAR(l.perLine.at("geodesic_mm")[n], std::stod(rows[n].at("geodesic_mm")), 1e-3);
        EXPECT_NEAR(l.perLine.at("euclidean_mm")[n], std::stod(rows[n].at("euclidean_mm")), 1e-3);
        EXPECT_NEAR(l.perLine.at("mean_fa")[n], std::stod(rows[n].at("mean_fa")), 1e-4);
        ASSERT_EQ(l.perPoint.at("fa")[n].size(), l.lines[n].size());
      }
    }
  }
  // The three files hold the same points.
  for (std::size_t f = 1; f < loaded.size(); ++f)
    for (std::size_t n = 0; n < 2; ++n) {
      ASSERT_EQ(loaded[f].lines[n].size(), loaded[0].lines[n].size());
      for (std::size_t p = 0; p < loaded[0].lines[n].size(); ++p)
        expectNear(loaded[f].lines[n][p], loaded[0].lines[n][p], 1e-4, "format " + std::to_string(f));
    }
}

// Measured (Release, x86-64), tool defaults (refined paths):
//   CC_body_R_lateral -> CC_body_L_lateral: crosses the midline plane
//     i = 55 (CC_body's) at 0.42 voxel from CC_body, mean FA 0.807
//     (traced only: 0.50 voxel, 0.812);
//   CST_L_low -> CST_L_high: superior share of the path length 0.953
//     (|dz| 36.9 mm of 38.7 mm; traced only: 0.939, of 39.3 mm).
// The issue's requirements: within 3 voxels, mean FA >= 0.5, "mainly
// superior" (taken as a superior share of at least 2/3, twice the share of
// a random direction, 1/3, and more than the other two axes together).
constexpr double kMidlineCrossingMaxVoxels = 3.0;
constexpr double kCallosalMinMeanFa = 0.5;
constexpr double kCorticospinalMinSuperiorShare = 2.0 / 3.0;

TEST_F(ToolPath, TheCallosalPathCrossesTheMidlineAtTheBodyAndStaysInWhiteMatter) {
  const auto seeds = seedTable();
  const NamedVoxel from = seeds.at("CC_body_R_lateral"), to = seeds.at("CC_body_L_lateral"),
                   body = seeds.at("CC_body");
  const ToolRun run =
      pathRun({"--seed-voxel", triple(from.index), "--target-voxel", triple(to.index), "-o", path("cc.trk")});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const LoadedStreamlines l = loadWithNibabel(path("cc.trk"));
  ASSERT_EQ(l.error, "");
  ASSERT_EQ(l.lines.size(), 1u);
  // Where the path crosses the plane i = 55 of CC_body (the midline).
  const std::vector<Vec3d>& p = l.lines[0];
  double crossing = INFINITY;
  for (std::size_t n = 1; n < p.size(); ++n) {
    const Vec3d a = rasToIndex(p[n - 1]), b = rasToIndex(p[n]);
    if ((a.x - body.index[0]) * (b.x - body.index[0]) > 0.0 || a.x == b.x) continue;
    const double t = (body.index[0] - a.x) / (b.x - a.x);
    const Vec3d c = a + t * (b - a);
    crossing = std::min(crossing, norm(c - Vec3d{double(body.index[0]), double(body.index[1]), double(body.index[2])}));
  }
  const double meanFa = l.perLine.at("mean_fa")[0];
  std::printf("[ measured ] CC_body_R_lateral -> CC_body_L_lateral: midline crossing %.2f voxel from CC_body, "
              "mean FA %.3f, geodesic %.1f mm, length %.1f mm\n",
              crossing, meanFa, l.perLine.at("geodesic_mm")[0], l.perLine.at("euclidean_mm")[0]);
  EXPECT_LE(crossing, kMidlineCrossingMaxVoxels);
  EXPECT_GE(meanFa, kCallosalMinMeanFa);
}

TEST_F(ToolPath, TheCorticospinalPathRunsMainlyAlongTheSuperiorAxis) {
  const auto seeds = seedTable();
  const NamedVoxel low = seeds.at("CST_L_low"), high = seeds.at("CST_L_high");
  const ToolRun run =
      pathRun({"--seed-voxel", triple(low.index), "--target-voxel", triple(high.index), "-o", path("cst.tck")});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const LoadedStreamlines l = loadWithNibabel(path("cst.tck"));
  ASSERT_EQ(l.error, "");
  ASSERT_EQ(l.lines.size(), 1u);
  double lx = 0, ly = 0, lz = 0, length = 0;
  for (std::size_t n = 1; n < l.lines[0].size(); ++n) {
    const Vec3d d = l.lines[0][n] - l.lines[0][n - 1];
    lx += std::abs(d.x);
    ly += std::abs(d.y);
    lz += std::abs(d.z);
    length += norm(d);
  }
  const double share = lz / length;
  const auto rows = readTsv(path("cst.tsv"));
  std::printf("[ measured ] CST_L_low -> CST_L_high: superior share %.3f (|dx| %.1f, |dy| %.1f, |dz| %.1f mm), "
              "mean FA %s, geodesic %s mm\n",
              share, lx, ly, lz, rows.at(0).at("mean_fa").c_str(), rows.at(0).at("geodesic_mm").c_str());
  EXPECT_GE(share, kCorticospinalMinSuperiorShare);
  EXPECT_GT(lz, lx + ly);
  EXPECT_GT(l.lines[0].back().z - l.lines[0].front().z, 30.0);  // CST_L_high is 36.85 mm above CST_L_low
}

// A path that ends at the brain's edge passes next to voxels outside the
// domain, which have no FA: the FA along it is interpolated over the
// domain's voxels only, so every point and the mean have a value in every
// file (the .tck header, the .vtk cell and point data, the table).
TEST_F(ToolPath, FaAlongAPathToTheBrainsEdgeIsAlwaysANumber) {
  for (const std::string name : {"edge.tck", "edge.vtk"}) {
    const ToolRun run = pathRun({"--seed-voxel", "55,54,15", "--target-voxel", "89,45,13", "-o", path(name), "-q"});
    ASSERT_EQ(run.exitCode, 0) << run.err;
    const LoadedStreamlines l = name == "edge.tck" ? loadWithNibabel(path(name)) : loadLegacyVtk(path(name));
    ASSERT_EQ(l.error, "");
    ASSERT_EQ(l.lines.size(), 1u);
    // .tck keeps per-path values as header entries, .vtk as cell data.
    const double meanFa =
        name == "edge.tck" ? std::stod(l.header.at("mean_fa")) : l.perLine.at("mean_fa")[0];
    EXPECT_TRUE(std::isfinite(meanFa)) << name;
    EXPECT_GT(meanFa, 0.0) << name;
    EXPECT_LT(meanFa, 1.0) << name;
    if (name == "edge.vtk") {
      for (const double fa : l.perPoint.at("fa")[0]) EXPECT_TRUE(std::isfinite(fa)) << name;
    }
    EXPECT_NE(readTsv(path("edge.tsv")).at(0).at("mean_fa"), "n/a");
  }
}

TEST_F(ToolPath, LabelTargetsEndAtEachRegionsVoxelNearestToTheSeeds) {
  const auto seeds = seedTable();
  imaging::ScalarImage labels = imaging::readScalarImage(sampleFile("dti_FA.nii.gz"));
  std::fill(labels.values.begin(), labels.values.end(), 0.f);
  const GridGeometry& g = labels.geometry;
  auto at = [&](const std::array<int, 3>& v) { return v[0] + g.size[0] * (v[1] + g.size[1] * v[2]); };
  labels.values[at(seeds.at("CC_body_L_lateral").index)] = 7.f;
  labels.values[at(seeds.at("CST_L_high").index)] = 3.f;
  imaging::writeScalarImage(path("targets.nii.gz"), g, labels.values);
  const ToolRun run = pathRun({"--seed-voxel", triple(seeds.at("CC_body").index), "--targets", path("targets.nii.gz"),
                               "-o", path("regions.vtk"), "--tsv", path("regions_summary.tsv")});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const auto rows = readTsv(path("regions_summary.tsv"));
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].at("target"), "label 3");
  EXPECT_EQ(rows[1].at("target"), "label 7");
  EXPECT_EQ(rows[0].at("target_k"), "20");
  EXPECT_EQ(rows[1].at("target_i"), "62");
  const LoadedStreamlines l = loadLegacyVtk(path("regions.vtk"));
  ASSERT_EQ(l.lines.size(), 2u);
  expectNear(l.lines[1].back(), seeds.at("CC_body_L_lateral").ras, kSeedTableTolerance, "label 7");
}

TEST_F(ToolPath, PathsToVoxelsAllOverTheBrainAllEndOnTheSeed) {
  // Every 97th brain voxel is a target of its own (about 1,400 paths,
  // border voxels of the brain and of the image slab included).
  imaging::ScalarImage labels = imaging::readScalarImage(sampleFile("dti_FA.nii.gz"));
  float next = 1.f;
  std::size_t brain = 0;
  for (float& value : labels.values) {
    const bool inBrain = value > 0.f;
    value = inBrain && brain++ % 97 == 0 ? next++ : 0.f;
  }
  imaging::writeScalarImage(path("targets.nii.gz"), labels.geometry, labels.values);
  const ToolRun run = pathRun({"--seed-voxel", "55,54,15", "--targets", path("targets.nii.gz"), "-o", path("all.tck"), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const auto rows = readTsv(path("all.tsv"));
  ASSERT_EQ(rows.size(), static_cast<std::size_t>(next - 1.f));
  std::size_t withFallback = 0;
  double worstRatio = 0.0;
  for (const auto& row : rows) {
    EXPECT_EQ(row.at("seed_i") + "," + row.at("seed_j") + "," + row.at("seed_k"), "55,54,15");
    withFallback += row.at("fallbacks") != "none" ? 1 : 0;
    const double geodesic = std::stod(row.at("geodesic_mm"));
    if (geodesic > 0.0) worstRatio = std::max(worstRatio, std::stod(row.at("metric_length_mm")) / geodesic);
  }
  std::printf("[ measured ] %zu paths from CC_body: %zu with a fallback, metric length / geodesic length at most %.3f\n",
              rows.size(), withFallback, worstRatio);
}

TEST_F(ToolPath, DiscretePathsArePolylinesThroughVoxelCentresFromSeedToTarget) {
  // The predecessor chain: with the default segment measure each link is a
  // measured straight segment, from the voxel where it starts, several
  // voxels long where the path runs straight.
  const auto seeds = seedTable();
  const auto seed = seeds.at("CST_L_low").index, target = seeds.at("CST_L_high").index;
  const ToolRun run = pathRun({"--seed-voxel", triple(seed), "--target-voxel", triple(target), "--discrete", "-o",
                               path("cst.trk")});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const LoadedStreamlines l = loadWithNibabel(path("cst.trk"));
  ASSERT_EQ(l.lines.size(), 1u);
  ASSERT_GE(l.lines[0].size(), 2u);
  double longest = 0.0;
  for (std::size_t n = 0; n < l.lines[0].size(); ++n) {
    const Vec3d c = rasToIndex(l.lines[0][n]);
    EXPECT_NEAR(c.x, std::round(c.x), 1e-3);
    EXPECT_NEAR(c.y, std::round(c.y), 1e-3);
    EXPECT_NEAR(c.z, std::round(c.z), 1e-3);
    if (n > 0) {
      const Vec3d d = c - rasToIndex(l.lines[0][n - 1]);
      const double step = std::max({std::abs(d.x), std::abs(d.y), std::abs(d.z)});
      EXPECT_GE(step, 1.0 - 1e-3) << "point " << n << " repeats the one before";
      longest = std::max(longest, step);
    }
  }
  const Vec3d first = rasToIndex(l.lines[0].front()), last = rasToIndex(l.lines[0].back());
  EXPECT_EQ(std::lround(first.x), seed[0]);
  EXPECT_EQ(std::lround(first.y), seed[1]);
  EXPECT_EQ(std::lround(first.z), seed[2]);
  EXPECT_EQ(std::lround(last.x), target[0]);
  EXPECT_EQ(std::lround(last.y), target[1]);
  EXPECT_EQ(std::lround(last.z), target[2]);
  std::printf("[ measured ] discrete path: %zu points, longest segment %.0f voxel steps\n", l.lines[0].size(),
              longest);
  EXPECT_GT(longest, 1.5);
}

TEST_F(ToolPath, BadRequestsFailWithTheirExitCodeAndLeaveNoFile) {
  const auto seeds = seedTable();
  const std::string seed = triple(seeds.at("CC_body").index);
  struct Case {
    std::vector<std::string> options;
    int exitCode;
    std::string message;
  };
  const std::vector<Case> cases = {
      {{"--seed-voxel", seed, "--target-voxel", "0,0,0", "-o", path("p.tck")}, 4, "target voxel (0, 0, 0) lies outside the domain"},
      {{"--seed-voxel", seed, "--target-voxel", "200,0,0", "-o", path("p.tck")}, 4, "lies outside the image"},
      {{"--seed-voxel", seed, "-o", path("p.tck")}, 2, "no target"},
      {{"--seed-voxel", seed, "--target-voxel", seed, "-o", path("p.nii")}, 2, "unsupported output format"},
      {{"--seed-voxel", seed, "--target-voxel", seed, "--step", "0", "-o", path("p.tck")}, 2, "--step"},
      {{"--seed-voxel", seed, "--target-voxel", seed, "-o", path("missing/p.tck")}, 5, "does not exist"},
      {{"--seed-voxel", seed, "--targets", sampleFile("missing.nii.gz"), "-o", path("p.tck")}, 3, "missing.nii.gz"},
  };
  for (const Case& c : cases) {
    const ToolRun run = pathRun(c.options);
    EXPECT_EQ(run.exitCode, c.exitCode) << run.err;
    EXPECT_NE(run.err.find(c.message), std::string::npos) << run.err;
    EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
    EXPECT_TRUE(listFolder(folder()).empty());
  }
}


// ---------------------------------------------------------------------------
// stvd connectivity

class ToolConnectivity : public ToolPath {
 protected:
  /// Labels 1..n at single voxels (value 0 elsewhere) on the sample's grid.
  std::string writeLabels(const std::vector<std::array<int, 3>>& voxels, const std::string& name,
                          float firstLabel = 1.f) {
    imaging::ScalarImage labels = imaging::readScalarImage(sampleFile("dti_FA.nii.gz"));
    std::fill(labels.values.begin(), labels.values.end(), 0.f);
    const GridGeometry& g = labels.geometry;
    for (std::size_t n = 0; n < voxels.size(); ++n)
      labels.values[voxels[n][0] + g.size[0] * (voxels[n][1] + g.size[1] * voxels[n][2])] = firstLabel + float(n);
    imaging::writeScalarImage(path(name), g, labels.values);
    return path(name);
  }
  ToolRun connectivityRun(const std::vector<std::string>& options) {
    std::vector<std::string> args{"connectivity", sampleFile(kDipy)};
    args.insert(args.end(), options.begin(), options.end());
    return runTool(args);
  }
};

std::string slurpFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

TEST_F(ToolConnectivity, EveryOrderedPairGetsThePathToolsDistanceAndTheLengthRatio) {
  const auto seeds = seedTable();
  const std::vector<std::string> names{"CC_body_R_lateral", "CC_body_L_lateral", "CST_L_high"};
  std::vector<std::array<int, 3>> voxels;
  for (const auto& name : names) voxels.push_back(seeds.at(name).index);
  const std::string labels = writeLabels(voxels, "regions.nii.gz");
  const ToolRun run = connectivityRun({"--labels", labels, "-o", path("table.tsv"), "--threads", "2"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const auto rows = readTsv(path("table.tsv"));
  ASSERT_EQ(rows.size(), 6u);
  // The same pairs through `stvd path`, one run per region A as the seed
  // with the other regions as targets (in the table's order).
  for (std::size_t a = 0; a < voxels.size(); ++a) {
    std::vector<std::string> options{"--seed-voxel", triple(voxels[a]), "-o", path("pair.tck"), "-q"};
    for (std::size_t b = 0; b < voxels.size(); ++b)
      if (b != a) options.insert(options.end(), {"--target-voxel", triple(voxels[b])});
    const ToolRun p = pathRun(options);
    ASSERT_EQ(p.exitCode, 0) << p.err;
    const auto pathRows = readTsv(path("pair.tsv"));
    ASSERT_EQ(pathRows.size(), voxels.size() - 1);
    for (std::size_t n = 0; n < pathRows.size(); ++n) {
      const auto& row = rows.at(a * (voxels.size() - 1) + n);
      const auto& pathRow = pathRows[n];
      ASSERT_EQ(std::stoul(row.at("region_a")), a + 1);
      EXPECT_EQ(row.at("geodesic_mm"), pathRow.at("geodesic_mm")) << names[a] << " -> " << pathRow.at("target");
      EXPECT_EQ(row.at("path_mm"), pathRow.at("euclidean_mm")) << names[a] << " -> " << pathRow.at("target");
      EXPECT_NEAR(std::stod(row.at("connectivity")),
                  std::stod(pathRow.at("euclidean_mm")) / std::stod(pathRow.at("geodesic_mm")), 1e-3);
    }
  }
}

TEST_F(ToolConnectivity, TheTableDoesNotDependOnTheNumberOfThreads) {
  const auto seeds = seedTable();
  std::vector<std::array<int, 3>> voxels;
  for (const std::string name : {"CC_genu", "CC_splenium", "CST_L", "CST_R", "CST_R_low", "CST_R_high"})
    voxels.push_back(seeds.at(name).index);
  const std::string labels = writeLabels(voxels, "six_seeds.nii.gz");
  ASSERT_EQ(connectivityRun({"--labels", labels, "-o", path("one.tsv"), "--threads", "1", "-q"}).exitCode, 0);
  ASSERT_EQ(connectivityRun({"--labels", labels, "-o", path("three.tsv"), "--threads", "3", "-q"}).exitCode, 0);
  EXPECT_EQ(readTsv(path("one.tsv")).size(), voxels.size() * (voxels.size() - 1));
  EXPECT_EQ(slurpFile(path("one.tsv")), slurpFile(path("three.tsv")));
}

// --matrix and --matrix-index: the table's values as square matrices in
// label order (labels deliberately not 1..n), as tck2connectome users load
// them: '#' header lines, then N rows of N comma-separated numbers.
TEST_F(ToolConnectivity, MatricesHoldTheTablesValuesInLabelOrder) {
  const auto seeds = seedTable();
  const std::vector<std::array<int, 3>> voxels{seeds.at("CC_genu").index, seeds.at("CST_L").index,
                                               seeds.at("CST_R").index};
  const std::string labels = writeLabels(voxels, "regions.nii.gz", 7.f);  // labels 7, 8, 9
  const ToolRun run = connectivityRun({"--labels", labels, "-o", path("table.tsv"), "--matrix", path("d.csv"),
                                       "--matrix-index", path("ci.csv"), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const auto rows = readTsv(path("table.tsv"));
  for (const auto& [file, column] :
       std::vector<std::pair<std::string, std::string>>{{"d.csv", "geodesic_mm"}, {"ci.csv", "connectivity"}}) {
    std::ifstream in(path(file));
    std::string line, labelLine;
    std::vector<std::vector<double>> matrix;
    while (std::getline(in, line)) {
      if (line.rfind("# labels: ", 0) == 0) labelLine = line.substr(10);
      if (line.empty() || line[0] == '#') continue;
      std::istringstream cells(line);
      std::string cell;
      matrix.emplace_back();
      while (std::getline(cells, cell, ',')) matrix.back().push_back(std::stod(cell));
    }
    EXPECT_EQ(labelLine, "7,8,9") << file;
    ASSERT_EQ(matrix.size(), 3u) << file;
    for (std::size_t a = 0; a < 3; ++a) {
      ASSERT_EQ(matrix[a].size(), 3u) << file;
      EXPECT_TRUE(std::isnan(matrix[a][a])) << file;  // no value on the diagonal (docs/paths.md)
      for (std::size_t b = 0; b < 3; ++b) {
        if (a == b) continue;
        const auto& row = rows.at(a * 2 + (b < a ? b : b - 1));
        ASSERT_EQ(row.at("region_a"), std::to_string(7 + a));
        ASSERT_EQ(row.at("region_b"), std::to_string(7 + b));
        EXPECT_NEAR(matrix[a][b], std::stod(row.at(column)), 1e-4) << file << " " << a << "," << b;
      }
    }
  }
}

TEST_F(ToolConnectivity, BadLabelsFailWithTheirExitCodeAndLeaveNoTable) {
  const auto seeds = seedTable();
  const std::string one = writeLabels({seeds.at("CC_body").index}, "one.nii.gz");
  ToolRun run = connectivityRun({"--labels", one, "-o", path("table.tsv")});
  EXPECT_EQ(run.exitCode, 4) << run.err;
  EXPECT_NE(run.err.find("fewer than two regions"), std::string::npos) << run.err;
  const std::string fractional =
      writeLabels({seeds.at("CC_body").index, seeds.at("CST_L").index}, "fractional.nii.gz", 1.5f);
  run = connectivityRun({"--labels", fractional, "-o", path("table.tsv")});
  EXPECT_EQ(run.exitCode, 3) << run.err;
  EXPECT_NE(run.err.find("is not an integer"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(path("table.tsv")));
}

TEST_F(ToolConnectivity, AnFaThresholdOnMetricTensorsIsRefusedAsByTheOtherCommands) {
  const auto seeds = seedTable();
  const std::string two = writeLabels({seeds.at("CC_body").index, seeds.at("CST_L").index}, "two.nii.gz");
  const ToolRun run = connectivityRun(
      {"--labels", two, "-o", path("table.tsv"), "--tensor-kind", "metric", "--fa-threshold", "0.2"});
  EXPECT_EQ(run.exitCode, 2) << run.err;
  EXPECT_NE(run.err.find("--fa-threshold applies to --tensor-kind diffusion only"), std::string::npos) << run.err;
  EXPECT_FALSE(std::filesystem::exists(path("table.tsv")));
}

}  // namespace
}  // namespace stvd::testing
