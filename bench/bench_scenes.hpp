// The two exact-metric scenes the benchmarks run on: a constant tensor with
// an oblique principal direction, and the curved pull-back metric of
// tests/core/exact_metrics.hpp, on an n^3 grid with unit spacing.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "exact_metrics.hpp"
#include "relative_error.hpp"
#include "stvd/system/large_array.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd::bench {

struct Scene {
  std::string name;
  VoxelGridDomain domain;
  RiemannianMetric metric;
  VertexId source = 0;
  /// Exact distance per vertex; negative where no closed form applies.
  std::vector<double> exact;
  double maxAnisotropy = 1.0;

  test::RelativeErrors errorsOf(const PropagationResult& r) const {
    test::RelativeErrors e;
    for (VertexId v = 0; v < domain.vertexCount(); ++v)
      if (exact[v] > 0.0) e.add(r.distance[v], exact[v]);
    return e;
  }
};

inline GridGeometry cube(int n) {
  GridGeometry g;
  g.size = {std::size_t(n), std::size_t(n), std::size_t(n)};
  return g;
}

/// G = I + (gamma^2 - 1) d d^T with d along (1, 2, 3), source at the centre.
inline Scene constantScene(int n, double gamma, const Stencil& stencil) {
  VoxelGridDomain domain(cube(n), stencil);
  const test::Mat3 g = test::uniaxialTensor(gamma, {1.0, 2.0, 3.0});
  Scene s{"constant gamma " + std::to_string(int(gamma)), domain,
          RiemannianMetric::constant(domain.vertexCount(), test::toSymTensor(g)),
          domain.vertexAt(n / 2, n / 2, n / 2), {}, gamma};
  const Vec3d x0 = domain.physicalPoint(s.source);
  s.exact.resize(domain.vertexCount());
  for (VertexId v = 0; v < domain.vertexCount(); ++v)
    s.exact[v] = v == s.source ? -1.0 : test::tensorNorm(g, domain.physicalPoint(v) - x0);
  return s;
}

/// The pull-back of the Euclidean metric through
/// phi(x) = diag(gamma, 1, 1) h(R (x - c)), h the shear
/// h(u) = (u1 + a1 sin(w1 u2), u2, u3 + a3 sin(w3 u1)) with periods of 0.8
/// and 1 grid width and largest slopes a1 w1 = `slope`, a3 w3 = 0.92 `slope`
/// (the bending of the anisotropy's directions). Exact distances are
/// evaluated on every `stride`-th voxel along each axis whose straight
/// image segment stays inside phi(box).
inline Scene pullbackScene(int n, double gamma, const Stencil& stencil, int stride,
                           double slope = 0.49) {
  VoxelGridDomain domain(cube(n), stencil);
  test::TriangularPullbackMap map;
  map.r = test::rotation({0.4, 0.3, -1.0}, 0.9);
  map.centre = {0.5 * (n - 1), 0.5 * (n - 1), 0.5 * (n - 1)};
  map.gamma = gamma;
  map.w1 = 2.0 * test::kPi / (n / 1.25);
  map.a1 = slope / map.w1;
  map.w3 = 2.0 * test::kPi / n;
  map.a3 = 0.92 * slope / map.w3;
  std::vector<SymTensor3> tensors = makeLargeArray(domain.vertexCount(), SymTensor3{});
  double maxAnisotropy = 1.0;
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    const test::Mat3 g = map.metric(domain.physicalPoint(v));
    tensors[v] = test::toSymTensor(g);
    maxAnisotropy = std::max(maxAnisotropy, test::anisotropy(g));
  }
  char name[64];
  std::snprintf(name, sizeof name, "pull-back gamma %g, shear slope %.2f", gamma, slope);
  Scene s{name, domain,
          RiemannianMetric(std::move(tensors)), domain.vertexAt(n / 2 - 3, n / 2 + 2, n / 2 - 1),
          std::vector<double>(domain.vertexCount(), -1.0), maxAnisotropy};
  const Vec3d a = map(domain.physicalPoint(s.source));
  const double last = n - 1;
  for (int k = 0; k < n; k += stride)
    for (int j = 0; j < n; j += stride)
      for (int i = 0; i < n; i += stride) {
        const VertexId v = domain.vertexAt(i, j, k);
        if (v == s.source) continue;
        const Vec3d b = map(domain.physicalPoint(v));
        // A step delta in the image moves the preimage by
        // |R^T J_h^-1 S^-1 delta| <= (1 + slope)^2 |S^-1 delta|, so
        // N = 2 (1 + slope)^2 |S^-1 (b - a)| samples keep consecutive
        // preimages within 0.5 voxel.
        const Vec3d unscaled{(b.x - a.x) / gamma, b.y - a.y, b.z - a.z};
        const double stretch = (1.0 + slope) * (1.0 + slope);
        const int samples = std::max(2, int(std::ceil(2.0 * stretch * norm(unscaled))));
        bool inside = true;
        for (int t = 1; t <= samples && inside; ++t) {
          const Vec3d x = map.inverse(a + (double(t) / samples) * (b - a));
          inside = x.x >= 0 && x.y >= 0 && x.z >= 0 && x.x <= last && x.y <= last && x.z <= last;
        }
        if (inside) s.exact[v] = norm(b - a);
      }
  return s;
}

}  // namespace stvd::bench
