// Geodesic distances under a constant anisotropic metric, computed with the
// installed stvd library and checked against the exact answer.
//
// For a constant metric tensor G the geodesics are straight lines and the
// distance from the seed s to x is sqrt((x - s)^T G (x - s)). Dijkstra on a
// 26-neighbourhood can only follow the stencil's directions and overestimates
// it; Short-Term Vector Dijkstra sums the last k edge vectors of a path and
// measures them as one vector, which removes most of that error.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "stvd/stvd.hpp"

namespace {

// STVD memory depth: how many edges back along a path are summed into one
// vector (1 is plain Dijkstra). Chosen here rather than taken from
// stvd::kDefaultMemoryDepth so that the bound below stays tied to it.
constexpr int kMemoryDepth = 8;

// Largest relative error of STVD accepted on this grid. With k = 8 and the
// 26-neighbourhood it measures 3.7 % (at a voxel 11 mm from the seed, in a
// direction that no short combination of stencil offsets matches), Dijkstra
// 31 %: the bound fails the run for a broken build or install, not for the
// method's own error.
constexpr double kStvdRelativeErrorBound = 0.05;

double exactDistance(const stvd::SymTensor3& g, stvd::Vec3d d) {
  return std::sqrt(g.xx * d.x * d.x + g.yy * d.y * d.y + g.zz * d.z * d.z +
                   2.0 * (g.xy * d.x * d.y + g.xz * d.x * d.z + g.yz * d.y * d.z));
}

// Largest |computed - exact| / exact over all voxels but the seed.
double maxRelativeError(const stvd::VoxelGridDomain& domain, const stvd::SymTensor3& g,
                        stvd::VertexId seed, const std::vector<double>& distance) {
  const stvd::Vec3d s = domain.physicalPoint(seed);
  double worst = 0.0;
  for (stvd::VertexId v = 0; v < domain.vertexCount(); ++v) {
    if (v == seed) continue;
    const double exact = exactDistance(g, domain.physicalPoint(v) - s);
    worst = std::max(worst, std::abs(distance[v] - exact) / exact);
  }
  return worst;
}

}  // namespace

int main() {
  // A 31 x 31 x 21 grid with 1 x 1 x 1.5 mm voxels.
  stvd::GridGeometry geometry;
  geometry.size = {31, 31, 21};
  geometry.spacing = {1.0, 1.0, 1.5};
  const stvd::VoxelGridDomain domain(geometry, stvd::Stencil::full26());

  // G = R diag(1, 2, 4) R^T with R a rotation by 30 degrees about z: moving
  // along the rotated third axis costs twice as much per millimetre as along
  // the first.
  const double pi = std::acos(-1.0);
  const double c = std::cos(pi / 6), s = std::sin(pi / 6);
  const double l1 = 1.0, l2 = 2.0, l3 = 4.0;
  stvd::SymTensor3 g;
  g.xx = static_cast<float>(l1 * c * c + l2 * s * s);
  g.xy = static_cast<float>((l1 - l2) * c * s);
  g.yy = static_cast<float>(l1 * s * s + l2 * c * c);
  g.zz = static_cast<float>(l3);
  const auto metric = stvd::RiemannianMetric::constant(domain.vertexCount(), g);

  const stvd::VertexId seed = domain.vertexAt(15, 15, 10);
  const stvd::PropagationResult stvdResult =
      stvd::shortTermVectorDijkstra(domain, metric, {seed}, kMemoryDepth);
  const stvd::PropagationResult dijkstraResult = stvd::dijkstra(domain, metric, {seed});

  std::printf("voxel          exact     STVD(k=%d)  Dijkstra\n", kMemoryDepth);
  const int probes[][3] = {{30, 15, 10}, {15, 30, 10}, {15, 15, 20}, {25, 20, 10},
                           {28, 22, 17}, {0, 3, 0},    {30, 30, 20}};
  for (const auto& p : probes) {
    const stvd::VertexId v = domain.vertexAt(p[0], p[1], p[2]);
    const double exact = exactDistance(g, domain.physicalPoint(v) - domain.physicalPoint(seed));
    std::printf("(%2d,%2d,%2d)  %9.4f  %9.4f  %9.4f\n", p[0], p[1], p[2], exact,
                stvdResult.distance[v], dijkstraResult.distance[v]);
  }

  const double stvdError = maxRelativeError(domain, g, seed, stvdResult.distance);
  const double dijkstraError = maxRelativeError(domain, g, seed, dijkstraResult.distance);
  std::printf("largest relative error over %u voxels: STVD %.4f (bound %.4f), Dijkstra %.4f\n",
              domain.vertexCount() - 1, stvdError, kStvdRelativeErrorBound, dijkstraError);
  if (!(stvdError <= kStvdRelativeErrorBound)) {
    std::fprintf(stderr, "stvd_consumer: STVD error %.4f exceeds the bound %.4f\n", stvdError,
                 kStvdRelativeErrorBound);
    return 1;
  }
  return 0;
}
