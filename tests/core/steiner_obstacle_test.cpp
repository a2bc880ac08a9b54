// Steiner-point propagation around masked voxels. A cube with a masked
// corner is not a cell, so a wall of masked voxels with a square hole
// leaves a domain made of the near half-space, a tube through the hole and
// the far half-space. Its geodesic distances under a constant norm are known
// by a small convex minimisation, and no Steiner distance may fall below
// them: every Steiner path is a polyline inside the cells. STVD's vector
// sums, by contrast, jump over masked voxels next to the hole (the sum of
// edges that go around a corner is measured as the straight vector through
// it), so its distances behind the wall are too short.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "exact_metrics.hpp"
#include "method_cases.hpp"
#include "relative_error.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"

namespace stvd {
namespace {

using test::RelativeErrors;

/// The wall is the index plane k = kWall, open in the square hole
/// [kHoleLo, kHoleHi]^2 of (i, j).
constexpr int kWall = 7, kHoleLo = 8, kHoleHi = 11;

class WallWithHole {
 public:
  WallWithHole()
      : geometry_(test::orientedGrid({20, 20, 15}, {1.0, 1.25, 1.5}, {5.0, -7.5, 20.0},
                                     test::rotation({0.3, 1.0, -0.4}, 0.5))),
        mask_(geometry_.voxelCount(), 1),
        tensor_(test::uniaxialTensor(4.0, {0.5, -0.3, 0.8})) {
    for (int j = 0; j < 20; ++j)
      for (int i = 0; i < 20; ++i) {
        const bool hole = i >= kHoleLo && i <= kHoleHi && j >= kHoleLo && j <= kHoleHi;
        if (!hole) mask_[i + 20 * (j + 20 * kWall)] = 0;
      }
  }

  const GridGeometry& geometry() const { return geometry_; }
  const std::vector<std::uint8_t>& mask() const { return mask_; }
  const test::Mat3& tensor() const { return tensor_; }

  /// ||x(b) - x(a)|| for continuous indices a, b.
  double length(Vec3d a, Vec3d b) const {
    const Vec3d d = geometry_.indexToPhysicalOffset(b.x - a.x, b.y - a.y, b.z - a.z);
    return test::tensorNorm(tensor_, d);
  }

  /// Geodesic distance from index s (k < kWall - 1) to index p (k <= kWall - 1
  /// or k >= kWall + 2) in the union of the cells. A path to the far side
  /// leaves the near half-space k <= kWall - 1 through the tube's floor at
  /// some h1 and enters the far half-space k >= kWall + 1 through its roof at
  /// some h2; all three pieces lie in convex sets, so the shortest path is
  /// straight in each, and the distance is the minimum over h1, h2 in the
  /// hole square of |h1 - s| + |h2 - h1| + |p - h2|, a smooth convex
  /// function (p is off the roof), minimised by cyclic coordinate descent.
  double exact(Vec3d s, Vec3d p) const {
    if (p.z <= kWall - 1) return length(s, p);
    double h[4];
    // Start where the straight segment crosses floor and roof, clamped.
    for (int n = 0; n < 2; ++n) {
      const double t = ((kWall - 1 + 2 * n) - s.z) / (p.z - s.z);
      h[2 * n] = std::clamp(s.x + t * (p.x - s.x), double(kHoleLo), double(kHoleHi));
      h[2 * n + 1] = std::clamp(s.y + t * (p.y - s.y), double(kHoleLo), double(kHoleHi));
    }
    auto f = [&](const double* x) {
      const Vec3d h1{x[0], x[1], double(kWall - 1)}, h2{x[2], x[3], double(kWall + 1)};
      return length(s, h1) + length(h1, h2) + length(h2, p);
    };
    const double ratio = 0.5 * (std::sqrt(5.0) - 1.0);
    for (int sweep = 0; sweep < 40; ++sweep)
      for (int c = 0; c < 4; ++c) {
        double lo = kHoleLo, hi = kHoleHi;
        for (int n = 0; n < 48; ++n) {
          const double m1 = hi - ratio * (hi - lo), m2 = lo + ratio * (hi - lo);
          h[c] = m1;
          const double f1 = f(h);
          h[c] = m2;
          if (f1 <= f(h)) hi = m2; else lo = m1;
        }
        h[c] = 0.5 * (lo + hi);
      }
    return f(h);
  }

 private:
  GridGeometry geometry_;
  std::vector<std::uint8_t> mask_;
  test::Mat3 tensor_;
};

TEST(SteinerObstacle, WallWithHoleIsPassedOnlyThroughTheHoleAndNeverCut) {
  const WallWithHole scene;
  const VoxelGridDomain domain(scene.geometry(), Stencil::full26(), scene.mask());
  const RiemannianMetric metric = RiemannianMetric::constant(domain.vertexCount(), test::toSymTensor(scene.tensor()));
  const VertexId source = domain.vertexAt(4, 5, 2);
  LanthierOptions options;
  options.steinerPoints = 4;
  const LanthierResult steiner = lanthierPropagate(domain, metric, {source}, options);
  const PropagationResult stvd = shortTermVectorDijkstra(domain, metric, {source}, 8);  // default measure
  // The chain rules (the paper's and the largest-norm one) at k = 16.
  std::vector<PropagationResult> chainRules;
  for (ChainMeasure measure : {ChainMeasure::ProjectionWeighted, ChainMeasure::LargestEdgeNorm}) {
    PropagationOptions o;
    o.chainMeasure = measure;
    chainRules.push_back(shortTermVectorDijkstra(domain, metric, {source}, 16, o));
  }

  const Vec3d s{4, 5, 2};
  RelativeErrors steinerNear, steinerFar, stvdFar;
  std::size_t far = 0, shadowed = 0, stvdCutting = 0;
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    if (!scene.mask()[v]) {
      ASSERT_EQ(steiner.distance[v], kUnreachable) << "vertex " << v;
      continue;
    }
    ASSERT_TRUE(std::isfinite(steiner.distance[v])) << "vertex " << v;
    const VoxelIndex c = domain.indexOf(v);
    // The hole and the plane above it: the exact distance has kinks there.
    if (v == source || c.k == kWall || c.k == kWall + 1) continue;
    const Vec3d p{double(c.i), double(c.j), double(c.k)};
    const double exact = scene.exact(s, p);
    ASSERT_GE(steiner.distance[v], exact * (1.0 - 1e-5)) << "vertex " << v << " cuts the wall";
    if (c.k < kWall) {
      steinerNear.add(steiner.distance[v], exact);
      continue;
    }
    ++far;
    shadowed += exact > 1.01 * scene.length(s, p) ? 1 : 0;
    steinerFar.add(steiner.distance[v], exact);
    stvdFar.add(stvd.distance[v], exact);
    stvdCutting += stvd.distance[v] < exact * (1.0 - 1e-3) ? 1 : 0;
    for (const PropagationResult& r : chainRules)
      ASSERT_GE(r.distance[v], exact * (1.0 - 1e-3)) << "vertex " << v << ": a chain rule cuts the wall";
  }
  test::reportMeasurement("Steiner M = 4, near side of the wall", steinerNear);
  test::reportMeasurement("Steiner M = 4, far side of the wall", steinerFar);
  test::reportMeasurement("STVD k = 8, far side of the wall", stvdFar);
  std::printf("[ measured ] far side: %zu voxels, %zu at least 1 %% longer than the straight line, "
              "%zu below the exact distance with STVD k = 8\n", far, shadowed, stvdCutting);
  // Not vacuous (measured: 1411 of the 2400 far-side voxels are in the
  // wall's shadow) ...
  EXPECT_GE(shadowed, far / 3);
  // ... and STVD, whose candidates are used only when their segments stay
  // in the domain's cells, never cuts the hole's edges there. (Before that
  // check, 2088 of these voxels came out more than 0.1 % below the exact
  // distance, by up to 23 %.)
  EXPECT_EQ(stvdCutting, 0u);
  // Measured mean errors: near side 0.0206 (as without the wall: the voxels
  // near the source dominate), far side 0.00179 (max 0.0236).
  EXPECT_LE(steinerNear.mean(), 0.028);
  EXPECT_LE(steinerFar.mean(), 0.0025);
  EXPECT_LE(steinerFar.max(), 0.033);
}

}  // namespace
}  // namespace stvd
