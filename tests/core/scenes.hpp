// Small deterministic inputs shared by the core specifications: oblique
// grids, a smooth spatially varying tensor field, masks, Randers fields and a
// reproducible pseudo-random sequence (std:: distributions differ between
// standard libraries, so they are not used).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "exact_metrics.hpp"
#include "kuhn_lattice.hpp"
#include "stvd/cell_mesh/cell_mesh_domain.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/metric/norms.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd::test {

/// splitmix64: a fixed, portable sequence of pseudo-random numbers.
class Random {
 public:
  explicit Random(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(next() >> 11) * 0x1.0p-53;
  }

 private:
  std::uint64_t state_;
};

/// `count` uniaxial tensors of anisotropy `gamma` (lambda_min = 1), each
/// with its expensive axis drawn uniformly on the sphere: a noisy field
/// whose neighbouring tensors disagree, and under which no path is shorter
/// than its Euclidean length.
inline std::vector<SymTensor3> randomAxisTensors(std::size_t count, double gamma, std::uint64_t seed) {
  Random random(seed);
  std::vector<SymTensor3> tensors(count);
  for (auto& t : tensors) {
    const double z = random.uniform(-1.0, 1.0), phi = random.uniform(0.0, 2.0 * kPi);
    const double r = std::sqrt(1.0 - z * z);
    t = toSymTensor(uniaxialTensor(gamma, {r * std::cos(phi), r * std::sin(phi), z}));
  }
  return tensors;
}

/// A grid of the given size with spacing (1, 1.5, 2), rotated index axes and
/// a non-zero origin.
inline GridGeometry obliqueGrid(std::array<std::size_t, 3> size) {
  return orientedGrid(size, {1.0, 1.5, 2.0}, {-31.5, 12.25, 107.0},
                      rotation({1.0, -2.0, 0.5}, 0.7));
}

/// A smooth field of SPD tensors whose anisotropy (about 5) and direction
/// vary across the grid: the pull-back metric of a sheared, stretched map.
inline std::vector<SymTensor3> smoothVaryingTensors(const VoxelGridDomain& domain) {
  TriangularPullbackMap map;
  map.r = rotation({0.4, 0.3, -1.0}, 0.9);
  map.centre = domain.physicalPoint(domain.vertexAt(0, 0, 0));
  map.gamma = 5.0;
  map.a1 = 3.0;
  map.w1 = 2.0 * kPi / 80.0;
  map.a3 = 2.0;
  map.w3 = 2.0 * kPi / 60.0;
  std::vector<SymTensor3> tensors(domain.vertexCount());
  for (VertexId v = 0; v < domain.vertexCount(); ++v)
    tensors[v] = toSymTensor(map.metric(domain.physicalPoint(v)));
  return tensors;
}

/// A Randers field with the tensors above and a drift that turns across the
/// grid, at 60 % of the largest strength the norm allows at every voxel.
inline std::vector<RandersNorm::VertexParams> smoothVaryingRanders(const VoxelGridDomain& domain) {
  const std::vector<SymTensor3> tensors = smoothVaryingTensors(domain);
  std::vector<RandersNorm::VertexParams> params(domain.vertexCount());
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    const VoxelIndex c = domain.indexOf(v);
    const double angle = 0.15 * c.i + 0.1 * c.k;
    const Vec3d direction{std::cos(angle), std::sin(angle), 0.3};
    // omega = 0.6 * M u / sqrt(u^T M u) gives omega^T M^-1 omega = 0.36.
    const SymTensor3& m = tensors[v];
    const Vec3f mu = m.apply(toFloat(direction));
    const float scale = 0.6f / std::sqrt(m.quadraticForm(toFloat(direction)));
    params[v] = {m, scale * mu};
  }
  return params;
}

/// One byte per voxel: 1 inside the ball of the given centre and radius
/// (in index units), 0 outside.
inline std::vector<std::uint8_t> ballMask(const GridGeometry& geometry, Vec3d centre,
                                          double radius) {
  std::vector<std::uint8_t> mask(geometry.voxelCount(), 0);
  std::size_t v = 0;
  for (std::size_t k = 0; k < geometry.size[2]; ++k)
    for (std::size_t j = 0; j < geometry.size[1]; ++j)
      for (std::size_t i = 0; i < geometry.size[0]; ++i, ++v) {
        const Vec3d d = Vec3d{double(i), double(j), double(k)} - centre;
        mask[v] = norm(d) <= radius ? 1 : 0;
      }
  return mask;
}

/// A box of n[0] x n[1] x n[2] cubes of the given edge lengths, each cube
/// split into the 6 tetrahedra of Kuhn's (Freudenthal's) subdivision along
/// its main diagonal; vertex (i, j, k) has index i + (n0+1) (j + (n1+1) k).
/// Interior vertices move by up to `jitter` times the edge lengths along
/// each axis (boundary vertices stay, so the mesh still fills the box).
struct TetrahedralBox {
  std::array<int, 3> n;
  std::vector<Vec3d> points;
  std::vector<CellMeshDomain::Tetrahedron> tets;

  VertexId id(int i, int j, int k) const {
    return static_cast<VertexId>(i + (n[0] + 1) * (j + (n[1] + 1) * k));
  }
  /// The tetrahedra of every cube (i, j, k) (its corner of smallest
  /// indices) for which keep(i, j, k) holds: a box with cubes cut out.
  template <class Keep>
  std::vector<CellMeshDomain::Tetrahedron> tetrahedraOfCubes(Keep&& keep) const {
    std::vector<CellMeshDomain::Tetrahedron> kept;
    for (std::size_t t = 0; t < tets.size(); ++t) {
      const int cube = static_cast<int>(t / 6);
      if (keep(cube % n[0], cube / n[0] % n[1], cube / (n[0] * n[1]))) kept.push_back(tets[t]);
    }
    return kept;
  }
};

inline TetrahedralBox kuhnTetrahedralBox(std::array<int, 3> n, Vec3d edge, double jitter,
                                        std::uint64_t seed) {
  TetrahedralBox box;
  box.n = n;
  Random random(seed);
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i) {
        Vec3d p{i * edge.x, j * edge.y, k * edge.z};
        const bool interior = i > 0 && j > 0 && k > 0 && i < n[0] && j < n[1] && k < n[2];
        if (interior && jitter > 0.0) {
          p.x += jitter * edge.x * random.uniform(-1.0, 1.0);
          p.y += jitter * edge.y * random.uniform(-1.0, 1.0);
          p.z += jitter * edge.z * random.uniform(-1.0, 1.0);
        }
        box.points.push_back(p);
      }
  // Cube (i, j, k) has tetrahedra 6 (i + n0 (j + n1 k)) .. + 5.
  const auto id = [&box](int i, int j, int k) { return box.id(i, j, k); };
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        forEachKuhnTetrahedron(i, j, k, id, [&box](const CellMeshDomain::Tetrahedron& t) { box.tets.push_back(t); });
  return box;
}

/// The geodesic distance between p and q in the L-shaped prism
/// [0, 2 half] x [0, 2 half] x [z0, z1] without the quadrant x > half,
/// y > half, under the constant metric diag(a^2, b^2, c^2): the straight
/// line where it stays in the prism, else around the notch x = y = half. The
/// scaling (a x, b y, c z) turns the metric into the Euclidean one and the
/// prism into another L-shaped prism, in which the shortest path bends
/// once, on the notch: unfolded about it, its length is the hypotenuse of
/// the two horizontal distances to the notch and the height difference.
inline double lShapedPrismDistance(double half, Vec3d p, Vec3d q, double a = 1.0, double b = 1.0, double c = 1.0) {
  // The parameters t in (0, 1) where the horizontal projection is in the
  // open missing quadrant: (x > half) and (y > half), two open intervals.
  double low = 0.0, high = 1.0;
  const double from[2] = {p.x, p.y}, to[2] = {q.x, q.y};
  for (int axis = 0; axis < 2; ++axis) {
    const double d = to[axis] - from[axis], t = (half - from[axis]) / d;
    if (d > 0.0) low = std::max(low, t);
    else if (d < 0.0) high = std::min(high, t);
    else if (from[axis] <= half) high = low;
  }
  const Vec3d e = q - p;
  if (!(low < high - 1e-12)) return std::sqrt(a * a * e.x * e.x + b * b * e.y * e.y + c * c * e.z * e.z);
  const double toP = std::hypot(a * (p.x - half), b * (p.y - half));
  const double toQ = std::hypot(a * (q.x - half), b * (q.y - half));
  return std::hypot(toP + toQ, c * e.z);
}

/// An L-shaped prism of unit Kuhn cubes: the box [0, 2 half] x [0, 2 half] x
/// [0, height] without the quadrant x > half, y > half. It is not convex
/// along one edge line, x = y = half (the notch); the vertices of the
/// missing quadrant belong to no tetrahedron.
struct LShapedPrism {
  int half;
  TetrahedralBox box;
  std::vector<CellMeshDomain::Tetrahedron> tets;

  LShapedPrism(int half, int height)
      : half(half),
        box(kuhnTetrahedralBox({2 * half, 2 * half, height}, {1.0, 1.0, 1.0}, 0.0, 1)),
        tets(box.tetrahedraOfCubes([half](int i, int j, int) { return i < half || j < half; })) {}
  /// Whether p lies in the prism (for points of the box).
  bool contains(Vec3d p) const { return p.x <= half || p.y <= half; }
  double distance(Vec3d p, Vec3d q, double a = 1.0, double b = 1.0, double c = 1.0) const {
    return lShapedPrismDistance(half, p, q, a, b, c);
  }
};

}  // namespace stvd::test
