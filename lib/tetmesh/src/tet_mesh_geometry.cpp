// Geometric checks and queries on a tetrahedral mesh.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "stvd/tetmesh/tet_mesh.hpp"

namespace stvd::tetmesh {
namespace {

double longestEdgeSquared(const std::array<Vec3d, 4>& p) {
  double longest = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) longest = std::max(longest, dot(p[j] - p[i], p[j] - p[i]));
  return longest;
}

/// %.3g: std::to_string prints small volumes as 0.000000.
std::string shortNumber(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", x);
  return text;
}

}  // namespace

double signedVolume(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& d) {
  return dot(b - a, cross(c - a, d - a)) / 6.0;
}

void validateTetMesh(const TetMesh& mesh, const std::string& nodeFile, const std::string& eleFile,
                     const TetMeshChecks& checks) {
  const std::size_t n = mesh.points.size();
  for (std::size_t v = 0; v < n; ++v) {
    const Vec3d p = mesh.points[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw TetMeshError(nodeFile + ": point " + std::to_string(v + mesh.firstIndex) + " has a non-finite coordinate");
  }
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const std::string name = "tetrahedron " + std::to_string(t + mesh.firstIndex);
    const auto& c = mesh.tets[t];
    for (int i = 0; i < 4; ++i) {
      if (c[i] >= n)
        throw TetMeshError(eleFile + ": " + name + " has corner " + std::to_string(std::int64_t{c[i]} + mesh.firstIndex) +
                           " out of range");
      for (int j = 0; j < i; ++j)
        if (c[i] == c[j])
          throw TetMeshError(eleFile + ": " + name + " repeats corner " +
                             std::to_string(std::int64_t{c[i]} + mesh.firstIndex));
    }
    const std::array<Vec3d, 4> p{mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]], mesh.points[c[3]]};
    const double volume = signedVolume(p[0], p[1], p[2], p[3]);
    const double scale = std::pow(longestEdgeSquared(p), 1.5);
    if (!(std::abs(volume) > checks.degenerateRelativeVolume * scale))
      throw TetMeshError(eleFile + ": " + name + " is degenerate (volume " + shortNumber(volume) +
                         ", its corners are (nearly) coplanar or coincide)");
    if (volume < 0.0)
      throw TetMeshError(eleFile + ": " + name + " is inverted (negative volume " + shortNumber(volume) +
                         "; TetGen orders corners so that det(p1-p0, p2-p0, p3-p0) > 0)");
  }
}

std::int64_t findContainingTet(const std::vector<Vec3d>& points, const std::vector<std::array<VertexId, 4>>& tets,
                               const Vec3d& p, std::array<double, 4>* barycentric) {
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const auto& c = tets[t];
    const Vec3d a = points[c[0]], b = points[c[1]], d = points[c[2]], e = points[c[3]];
    const double total = signedVolume(a, b, d, e);
    if (total == 0.0) continue;
    // Barycentric coordinates as volume ratios; slightly negative ones still
    // count so that a point on a shared face is found in one of its tets.
    const double tolerance = -1e-9;
    const std::array<double, 4> w{signedVolume(p, b, d, e) / total, signedVolume(a, p, d, e) / total,
                                  signedVolume(a, b, p, e) / total, signedVolume(a, b, d, p) / total};
    if (w[0] < tolerance || w[1] < tolerance || w[2] < tolerance || w[3] < tolerance) continue;
    if (barycentric) *barycentric = w;
    return static_cast<std::int64_t>(t);
  }
  return -1;
}

std::int64_t findContainingTet(const TetMesh& mesh, const Vec3d& p) {
  return findContainingTet(mesh.points, mesh.tets, p);
}

VertexId nearestVertex(const TetMesh& mesh, const Vec3d& p) {
  VertexId best = kNoVertex;
  double bestDistance = std::numeric_limits<double>::infinity();
  for (std::size_t v = 0; v < mesh.points.size(); ++v) {
    const double d = dot(mesh.points[v] - p, mesh.points[v] - p);
    if (d < bestDistance) {
      bestDistance = d;
      best = static_cast<VertexId>(v);
    }
  }
  return best;
}

}  // namespace stvd::tetmesh
