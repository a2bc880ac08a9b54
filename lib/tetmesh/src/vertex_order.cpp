// Morton ordering of mesh vertices.
#include "stvd/tetmesh/vertex_order.hpp"

#include <algorithm>
#include <cstdint>
#include <numeric>

namespace stvd::tetmesh {
namespace {

/// The 21 low bits of x spread to every third bit.
std::uint64_t spreadBits(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

}  // namespace

VertexPermutation mortonOrder(const std::vector<Vec3d>& points) {
  VertexPermutation p;
  const std::size_t n = points.size();
  p.newToOld.resize(n);
  std::iota(p.newToOld.begin(), p.newToOld.end(), VertexId{0});
  p.oldToNew.resize(n);
  if (n == 0) return p;
  Vec3d lo = points[0], hi = points[0];
  for (const Vec3d& q : points) {
    lo = {std::min(lo.x, q.x), std::min(lo.y, q.y), std::min(lo.z, q.z)};
    hi = {std::max(hi.x, q.x), std::max(hi.y, q.y), std::max(hi.z, q.z)};
  }
  const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-300});
  const double scale = static_cast<double>((1u << 21) - 1) / extent;
  std::vector<std::uint64_t> code(n);
  for (std::size_t v = 0; v < n; ++v) {
    const Vec3d q = points[v];
    code[v] = spreadBits(static_cast<std::uint64_t>((q.x - lo.x) * scale)) |
              spreadBits(static_cast<std::uint64_t>((q.y - lo.y) * scale)) << 1 |
              spreadBits(static_cast<std::uint64_t>((q.z - lo.z) * scale)) << 2;
  }
  std::stable_sort(p.newToOld.begin(), p.newToOld.end(), [&](VertexId a, VertexId b) { return code[a] < code[b]; });
  for (std::size_t i = 0; i < n; ++i) p.oldToNew[p.newToOld[i]] = static_cast<VertexId>(i);
  return p;
}

std::vector<Vec3d> permutedPoints(const std::vector<Vec3d>& points, const VertexPermutation& p) {
  std::vector<Vec3d> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) out[i] = points[p.newToOld[i]];
  return out;
}

std::vector<std::array<VertexId, 4>> permutedTets(const std::vector<std::array<VertexId, 4>>& tets,
                                                  const VertexPermutation& p) {
  std::vector<std::array<VertexId, 4>> out(tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t)
    for (int c = 0; c < 4; ++c) out[t][c] = p.oldToNew[tets[t][c]];
  return out;
}

}  // namespace stvd::tetmesh
