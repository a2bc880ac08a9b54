// Dijkstra over a voxel grid under the convexified FOD norm (docs/fod.md,
// "Propagation"): two bundles of 5 voxels' width cross in the middle of a
// 25 x 25 x 3 grid, at 90 and at 45 degrees; each voxel's FOD has one lobe
// per bundle it lies in (two in the crossing), none outside them. A seed
// at one end of a bundle reaches the far end of its own bundle along it,
// straight through the crossing, at the cost of its length (1 per mm), and
// the far end of the other bundle by turning into it at the crossing,
// never cutting through the voxels of neither.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/fod_field.hpp"
#include "stvd/imaging/fod_metric.hpp"
#include "stvd/imaging/spherical_harmonics.hpp"
#include "stvd/propagation/predecessor_path.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd::testing {
namespace {

using namespace imaging;

constexpr int kN = 25, kC = 12, kHalfWidth = 2;

/// Adds a lobe along the LPS direction d to the coefficients (MRtrix3's
/// basis, scanner frame): h_l Y_lm(d), a function of u.d largest at d.
void addLobe(const FodField& f, float* c, const Vec3d& d) {
  const Vec3d s = f.toShFrame(d);
  const std::vector<double> y = evaluateShBasis(ShBasis::Tournier07, 8, s.x, s.y, s.z);
  for (int l = 0; l <= 8; l += 2)
    for (int m = -l; m <= l; ++m) c[l * (l + 1) / 2 + m] += static_cast<float>(std::exp(-0.02 * l * (l + 1)) * y[l * (l + 1) / 2 + m]);
}

struct Bundles {
  FodField field;
  Vec3d direction[2];  // unit, LPS; index axes are the LPS axes here
  /// Whether voxel (i, j) lies within kHalfWidth of bundle b's axis through the centre.
  bool inBundle(int b, int i, int j) const {
    const double x = i - kC, y = j - kC;
    const double along = x * direction[b].x + y * direction[b].y;
    const double dx = x - along * direction[b].x, dy = y - along * direction[b].y;
    return std::sqrt(dx * dx + dy * dy) <= kHalfWidth + 1e-9;
  }
};

Bundles bundles(double degrees) {
  Bundles b;
  FodField& f = b.field;
  f.geometry.size = {kN, kN, 3};
  f.lmax = 8;
  f.basis = ShBasis::Tournier07;
  f.frame = FodFrame::Scanner;
  f.lpsToShFrame = lpsToFodFrame(FodFrame::Scanner, f.geometry);
  f.coefficients.assign(f.geometry.voxelCount() * 45, 0.f);
  b.direction[0] = {1, 0, 0};
  b.direction[1] = {std::cos(degrees * M_PI / 180), std::sin(degrees * M_PI / 180), 0};
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i)
        for (int bundle = 0; bundle < 2; ++bundle)
          if (b.inBundle(bundle, i, j))
            addLobe(f, f.coefficients.data() + 45 * (i + kN * (j + kN * k)), b.direction[bundle]);
  return b;
}

class FodDijkstra : public ::testing::TestWithParam<double> {};

TEST_P(FodDijkstra, ASeedReachesTheFarEndOfItsOwnBundleAlongIt) {
  const Bundles b = bundles(GetParam());
  const FodCostSampler sampler(b.field, defaultFodSampling(b.field.geometry));
  const FodStencilMetric metric = fodStencilMetric(sampler);
  const VoxelGridDomain domain(b.field.geometry, Stencil::full26());

  // Bundle 0 runs along i through j = kC; the seed is its end at i = 0.
  const VertexId seed = domain.vertexAt(0, kC, 1);
  PropagationOptions options;
  options.method = Method::Dijkstra;
  const PropagationResult r = propagate(domain, metric, {seed}, options);

  // Its far end: reached along the bundle, at its length.
  const VertexId farEnd = domain.vertexAt(kN - 1, kC, 1);
  EXPECT_NEAR(r.distance[farEnd], kN - 1, 1e-3 * (kN - 1));
  for (VertexId v : predecessorPath(r, farEnd)) {
    const int i = static_cast<int>(v % kN), j = static_cast<int>((v / kN) % kN), k = static_cast<int>(v / (kN * kN));
    EXPECT_EQ(j, kC) << "left the axis of its bundle at (" << i << ", " << j << ", " << k << ")";
    EXPECT_EQ(k, 1);
  }

  // The far end of the other bundle (its end beyond the crossing, on the
  // side of positive direction): along bundle 0 to the crossing, then along
  // bundle 1; every voxel of the path in one of the bundles, and its length
  // that of the two legs (steps along either bundle's direction cost 1 per
  // mm; the 45-degree bundle's diagonal steps are neighbour directions).
  const int reach = GetParam() == 90.0 ? kC : 12;
  const int ti = static_cast<int>(std::lround(kC + reach * b.direction[1].x));
  const int tj = static_cast<int>(std::lround(kC + reach * b.direction[1].y));
  const VertexId other = domain.vertexAt(ti, tj, 1);
  const double legs = kC + std::hypot(ti - kC, tj - kC);
  EXPECT_NEAR(r.distance[other], legs, 0.02 * legs);
  int turnedAt = -1;
  const std::vector<VertexId> path = predecessorPath(r, other);
  for (std::size_t s = 0; s < path.size(); ++s) {
    const int i = static_cast<int>(path[s] % kN), j = static_cast<int>((path[s] / kN) % kN);
    EXPECT_TRUE(b.inBundle(0, i, j) || b.inBundle(1, i, j)) << "a step through neither bundle at (" << i << ", " << j << ")";
    if (turnedAt < 0 && !b.inBundle(0, i, j)) turnedAt = static_cast<int>(s);
  }
  EXPECT_GT(turnedAt, 0);

  // Across the bundles the cost is far higher: the voxel beside the seed,
  // outside both bundles, is not reached for less than the floor's cost.
  const VertexId outside = domain.vertexAt(0, kC + kHalfWidth + 3, 1);
  EXPECT_GT(r.distance[outside], 3.0 * (kHalfWidth + 3));
}

INSTANTIATE_TEST_SUITE_P(CrossingAngles, FodDijkstra, ::testing::Values(90.0, 45.0));

// The table on several threads is the table on one: every voxel's F* is its
// own, whichever thread computes it, so the distances are bit-equal (on a
// domain mask too, whose voxels outside get the floor's cost).
TEST(FodStencilMetricThreads, TheDistancesAreBitEqualForAnyThreadCount) {
  const Bundles b = bundles(60.0);
  const FodCostSampler sampler(b.field, defaultFodSampling(b.field.geometry));
  std::vector<std::uint8_t> inDomain(b.field.geometry.voxelCount(), 1);
  for (std::size_t v = 0; v < inDomain.size(); v += 7) inDomain[v] = 0;
  inDomain[kC * kN + kN * kN] = 1;  // the seed (0, kC, 1)
  const VoxelGridDomain domain(b.field.geometry, Stencil::full26(), inDomain);
  PropagationOptions options;
  options.method = Method::Dijkstra;
  const VertexId seed = domain.vertexAt(0, kC, 1);
  const std::vector<double> one = propagate(domain, fodStencilMetric(sampler, &inDomain, 1), {seed}, options).distance;
  for (const unsigned threads : {2u, 3u, 0u}) {
    const std::vector<double> more =
        propagate(domain, fodStencilMetric(sampler, &inDomain, threads), {seed}, options).distance;
    ASSERT_EQ(more.size(), one.size());
    std::size_t reached = 0;
    for (std::size_t v = 0; v < one.size(); ++v) {
      reached += std::isfinite(one[v]);
      ASSERT_EQ(std::memcmp(&one[v], &more[v], sizeof(double)), 0) << "voxel " << v << " on " << threads << " threads";
    }
    EXPECT_GT(reached, one.size() / 2);
  }
}

// The sampling directions turn with the image's axes: the same FOD image
// (coefficients in the voxel frame, as DIPY writes them) given a rotated
// and flipped affine has the same table and the same distances, to float
// rounding (with directions fixed in LPS they differed by up to 5.6 %).
TEST(FodSamplingFrame, ARotatedAffineWithVoxelFrameCoefficientsGivesTheSameDistances) {
  // The bundles lie in the i-j plane, where the scanner frame of an
  // identity grid is the voxel frame turned by 180 degrees: the same even
  // FOD read in the voxel frame.
  Bundles b = bundles(60.0);
  b.field.frame = FodFrame::Voxel;
  b.field.geometry.spacing = {1.0, 1.25, 2.0};
  b.field.lpsToShFrame = lpsToFodFrame(FodFrame::Voxel, b.field.geometry);
  FodField turned = b.field;
  // Columns: the index axes in LPS; 35 degrees about (1, 2, 2) / 3, then
  // the j axis flipped (a left-handed grid, as many NIfTI files are).
  const double a = 35 * M_PI / 180, c = std::cos(a), s = std::sin(a);
  const double ux = 1.0 / 3, uy = 2.0 / 3, uz = 2.0 / 3;
  const double r[9] = {c + ux * ux * (1 - c),      ux * uy * (1 - c) - uz * s, ux * uz * (1 - c) + uy * s,
                       uy * ux * (1 - c) + uz * s, c + uy * uy * (1 - c),      uy * uz * (1 - c) - ux * s,
                       uz * ux * (1 - c) - uy * s, uz * uy * (1 - c) + ux * s, c + uz * uz * (1 - c)};
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) turned.geometry.direction[3 * row + col] = (col == 1 ? -1.0 : 1.0) * r[3 * row + col];
  turned.geometry.origin = {-40.0, 12.5, 7.0};
  turned.lpsToShFrame = lpsToFodFrame(FodFrame::Voxel, turned.geometry);

  const FodCostSampler samplerA(b.field, defaultFodSampling(b.field.geometry));
  const FodCostSampler samplerB(turned, defaultFodSampling(turned.geometry));
  const FodStencilMetric metricA = fodStencilMetric(samplerA, nullptr, 2);
  const FodStencilMetric metricB = fodStencilMetric(samplerB, nullptr, 2);
  double worstTable = 0;
  for (std::size_t v = 0; v < metricA.size(); ++v)
    for (int q = 0; q < 26; ++q)
      worstTable = std::max(worstTable, std::abs(double(metricB[v].cost[q]) - metricA[v].cost[q]) / metricA[v].cost[q]);
  EXPECT_LT(worstTable, 1e-5);

  const VoxelGridDomain domainA(b.field.geometry, Stencil::full26()), domainB(turned.geometry, Stencil::full26());
  PropagationOptions options;
  options.method = Method::Dijkstra;
  const VertexId seed = domainA.vertexAt(0, kC, 1);
  const std::vector<double> da = propagate(domainA, metricA, {seed}, options).distance;
  const std::vector<double> db = propagate(domainB, metricB, {seed}, options).distance;
  double worst = 0;
  for (std::size_t v = 0; v < da.size(); ++v)
    if (da[v] > 0) worst = std::max(worst, std::abs(db[v] - da[v]) / da[v]);
  std::printf("rotated, flipped affine: table within %.2g, distances within %.2g\n", worstTable, worst);
  EXPECT_LT(worst, 1e-5);
}

// The table reports to an Interrupter as an operation of its own and stops
// when asked, with the usual error and no table.
class CountingInterrupter : public Interrupter {
 public:
  explicit CountingInterrupter(int stopAt) : stopAt_(stopAt) {}
  void start(const char* name) override {
    names.push_back(name);
    ++starts;
  }
  void end() override { ++ends; }
  bool wasInterrupted(int percent) override {
    percents.push_back(percent);
    return static_cast<int>(percents.size()) >= stopAt_;
  }
  std::vector<std::string> names;
  std::vector<int> percents;
  int starts = 0, ends = 0;

 private:
  int stopAt_;
};

TEST(FodTableProgress, ReportsItsBlocksAndStopsWhenAskedWithTheUsualError) {
  const Bundles b = bundles(90.0);  // 1,875 voxels: 8 blocks of 256
  const FodCostSampler sampler(b.field, defaultFodSampling(b.field.geometry));
  const std::size_t blocks = (b.field.geometry.voxelCount() + kFodMetricBlockVoxels - 1) / kFodMetricBlockVoxels;
  ASSERT_GE(blocks, 6u);
  // Never interrupted: "FOD table" from 0 to 100 %, every block reported
  // on one thread (interval 0), and the same table as without a listener.
  {
    CountingInterrupter listener(1000);
    const FodStencilMetric heard = fodStencilMetric(sampler, nullptr, 1, &listener, 0.0);
    const FodStencilMetric silent = fodStencilMetric(sampler, nullptr, 1);
    EXPECT_EQ(listener.names, std::vector<std::string>{"FOD table"});
    EXPECT_EQ(listener.starts, 1);
    EXPECT_EQ(listener.ends, 1);
    ASSERT_EQ(listener.percents.size(), blocks + 2);
    EXPECT_EQ(listener.percents.front(), 0);
    EXPECT_EQ(listener.percents.back(), 100);
    EXPECT_TRUE(std::is_sorted(listener.percents.begin(), listener.percents.end()));
    for (std::size_t v = 0; v < heard.size(); ++v)
      EXPECT_EQ(std::memcmp(heard[v].cost, silent[v].cost, sizeof heard[v].cost), 0) << "voxel " << v;
  }
  // Interrupted after 3 blocks, on 1 and on 2 threads: Cancelled, no
  // further report, the operation ended once.
  for (const unsigned threads : {1u, 2u}) {
    CountingInterrupter listener(4);
    try {
      fodStencilMetric(sampler, nullptr, threads, &listener, 0.0);
      ADD_FAILURE() << "the table was not interrupted on " << threads << " threads";
    } catch (const Cancelled& e) {
      EXPECT_STREQ(e.what(), "FOD table was interrupted");
    }
    EXPECT_EQ(listener.percents.size(), 4u);
    EXPECT_LT(listener.percents.back(), 100);
    EXPECT_EQ(listener.starts, 1);
    EXPECT_EQ(listener.ends, 1);
  }
  // Asked to stop at its start: nothing computed.
  CountingInterrupter atOnce(1);
  EXPECT_THROW(fodStencilMetric(sampler, nullptr, 2, &atOnce), Cancelled);
  EXPECT_EQ(atOnce.percents, std::vector<int>{0});
}

}  // namespace
}  // namespace stvd::testing
