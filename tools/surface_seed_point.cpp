#include "surface_seed_point.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

namespace stvd::tool {
namespace {

constexpr double kZeroWeight = 1e-9;

/// The point of triangle abc closest to p, as barycentric weights (of a,
/// b, c): the Voronoi regions of the corners, edges and face in turn.
std::array<double, 3> closestOnTriangle(Vec3d p, Vec3d a, Vec3d b, Vec3d c) {
  const Vec3d ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {1, 0, 0};
  const Vec3d bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return {0, 1, 0};
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double t = d1 / (d1 - d3);
    return {1 - t, t, 0};
  }
  const Vec3d cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return {0, 0, 1};
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double t = d2 / (d2 - d6);
    return {1 - t, 0, t};
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double t = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - t, t};
  }
  const double denominator = 1.0 / (va + vb + vc);
  const double v = vb * denominator, w = vc * denominator;
  return {1 - v - w, v, w};
}

}  // namespace

SurfacePoint closestSurfacePoint(const surface_io::SurfaceMesh& mesh, Vec3d point) {
  SurfacePoint best;
  best.distance = std::numeric_limits<double>::infinity();
  const PolygonList& faces = mesh.faces;
  for (std::size_t f = 0; f < faces.faceCount(); ++f) {
    const std::uint32_t first = faces.faceStart[f], end = faces.faceStart[f + 1];
    for (std::uint32_t k = first + 1; k + 1 < end; ++k) {
      const VertexId corner[3] = {faces.faceVertex[first], faces.faceVertex[k], faces.faceVertex[k + 1]};
      const std::array<double, 3> w =
          closestOnTriangle(point, mesh.points[corner[0]], mesh.points[corner[1]], mesh.points[corner[2]]);
      const Vec3d q = w[0] * mesh.points[corner[0]] + w[1] * mesh.points[corner[1]] + w[2] * mesh.points[corner[2]];
      const double d = norm(point - q);
      if (!(d < best.distance)) continue;
      best.closest = q;
      best.distance = d;
      best.face = f;
      best.weights.clear();
      double total = 0.0;
      for (int c = 0; c < 3; ++c)
        if (w[c] > kZeroWeight) {
          best.weights.push_back({corner[c], w[c]});
          total += w[c];
        }
      for (auto& [v, weight] : best.weights) weight /= total;
    }
  }
  return best;
}

VertexId nearestVertex(const surface_io::SurfaceMesh& mesh, Vec3d point) {
  VertexId best = 0;
  double bestDistance = std::numeric_limits<double>::infinity();
  for (VertexId v = 0; v < mesh.points.size(); ++v) {
    const double d = norm(mesh.points[v] - point);
    if (d < bestDistance) {
      best = v;
      bestDistance = d;
    }
  }
  return best;
}

VertexId insertSurfacePoint(surface_io::SurfaceMesh& mesh, const SurfacePoint& p,
                            std::vector<std::size_t>& faceOrigin) {
  if (p.weights.size() == 1) return p.weights[0].first;
  const PolygonList old = mesh.faces;
  const VertexId added = static_cast<VertexId>(mesh.points.size());
  mesh.points.push_back(p.closest);

  // On a segment between two corners: an edge of the polygon, or a
  // diagonal of its fan (then it is inside the face).
  bool onEdge = false;
  VertexId a = 0, b = 0;
  if (p.weights.size() == 2) {
    a = p.weights[0].first;
    b = p.weights[1].first;
    const std::uint32_t first = old.faceStart[p.face], end = old.faceStart[p.face + 1];
    for (std::uint32_t c = first; c < end; ++c) {
      const VertexId u = old.faceVertex[c], w = old.faceVertex[c + 1 < end ? c + 1 : first];
      onEdge = onEdge || (u == a && w == b) || (u == b && w == a);
    }
  }

  PolygonList faces;
  std::vector<std::size_t> origin;
  std::vector<VertexId> polygon;
  for (std::size_t f = 0; f < old.faceCount(); ++f) {
    const std::uint32_t first = old.faceStart[f], end = old.faceStart[f + 1];
    if (!onEdge && f == p.face) {
      for (std::uint32_t c = first; c < end; ++c) {
        const VertexId triangle[3] = {old.faceVertex[c], old.faceVertex[c + 1 < end ? c + 1 : first], added};
        faces.add(triangle, triangle + 3);
        origin.push_back(faceOrigin[f]);
      }
      continue;
    }
    polygon.clear();
    for (std::uint32_t c = first; c < end; ++c) {
      const VertexId u = old.faceVertex[c], w = old.faceVertex[c + 1 < end ? c + 1 : first];
      polygon.push_back(u);
      if (onEdge && ((u == a && w == b) || (u == b && w == a))) polygon.push_back(added);
    }
    faces.add(polygon.begin(), polygon.end());
    origin.push_back(faceOrigin[f]);
  }
  mesh.faces = faces;
  faceOrigin = origin;
  return added;
}

}  // namespace stvd::tool
