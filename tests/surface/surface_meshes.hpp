// Surfaces generated for the specifications, each with the coordinates in
// which its exact distances are known: planes (badly shaped triangles,
// jittered quads), an icosphere, and prisms (a cylinder is developable, so
// its distances are those of the unrolled strip).
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <vector>

#include "../core/exact_metrics.hpp"
#include "stvd/surface/surface_domain.hpp"

namespace stvd::test {

struct GeneratedSurface {
  std::vector<Vec3d> points;
  PolygonList faces;
  /// Per vertex, coordinates of the developed plane (planes, prisms).
  std::vector<std::array<double, 2>> flat;
};

/// An nx x ny grid over [0, width] x [0, height] in the plane spanned by the
/// world vectors a1, a2 (orthonormal) through `origin`. Column widths vary
/// by a factor `stretch` (wide and narrow columns alternate), interior
/// points move by up to `jitter` of their cell, and each cell is split
/// along a random diagonal, or kept as a quad when `quads`.
inline GeneratedSurface planeMesh(int nx, int ny, double width, double height, double stretch,
                                  double jitter, bool quads, std::uint32_t seed,
                                  Vec3d origin = {0, 0, 0}, Vec3d a1 = {1, 0, 0},
                                  Vec3d a2 = {0, 1, 0}) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::vector<double> xs(nx + 1, 0.0), ys(ny + 1, 0.0);
  for (int i = 1; i <= nx; ++i) xs[i] = xs[i - 1] + (i % 2 ? 1.0 : stretch);
  for (int i = 0; i <= nx; ++i) xs[i] *= width / xs[nx];
  for (int j = 0; j <= ny; ++j) ys[j] = height * j / ny;
  GeneratedSurface s;
  auto id = [nx](int i, int j) { return static_cast<VertexId>(j * (nx + 1) + i); };
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      double x = xs[i], y = ys[j];
      if (i > 0 && i < nx) x += jitter * unit(rng) * 0.5 * std::min(xs[i] - xs[i - 1], xs[i + 1] - xs[i]);
      if (j > 0 && j < ny) y += jitter * unit(rng) * 0.5 * (height / ny);
      s.flat.push_back({x, y});
      s.points.push_back(origin + x * a1 + y * a2);
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const VertexId a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (quads) {
        s.faces.add({a, b, c, d});
      } else if (rng() % 2) {
        s.faces.add({a, b, c});
        s.faces.add({a, c, d});
      } else {
        s.faces.add({a, b, d});
        s.faces.add({b, c, d});
      }
    }
  return s;
}

// A plane tilted in space (through (3, -2, 1), spanned by the orthonormal
// tiltedPlaneAxes), 40 x 40 cells over 10 x 10, columns alternating in
// width by 1 : 0.15, jittered, random diagonals: many needles and obtuse
// triangles. flat holds the plane coordinates.
inline std::array<Vec3d, 2> tiltedPlaneAxes() {
  return {normalized({1, 1, 0}), normalized({-0.5, 0.5, 1})};
}
inline GeneratedSurface badlyShapedTiltedPlane(bool quads = false) {
  const auto a = tiltedPlaneAxes();
  return planeMesh(40, 40, 10.0, 10.0, 0.15, 0.6, quads, 7, {3, -2, 1}, a[0], a[1]);
}

/// The plane's 2x2 tensor g = {g11, g12, g22} as a world tensor on the
/// tilted plane: G_world = sum g_ij a_i a_j^T, singular across the plane
/// (surface metric builders keep its tangential part).
inline SymTensor3 tiltedPlaneWorldTensor(const std::array<double, 3>& g) {
  const auto [a1, a2] = tiltedPlaneAxes();
  auto entry = [&](double u1, double u2, double w1, double w2) {
    return static_cast<float>(g[0] * u1 * w1 + g[1] * (u1 * w2 + u2 * w1) + g[2] * u2 * w2);
  };
  return {entry(a1.x, a2.x, a1.x, a2.x), entry(a1.x, a2.x, a1.y, a2.y), entry(a1.x, a2.x, a1.z, a2.z),
          entry(a1.y, a2.y, a1.y, a2.y), entry(a1.y, a2.y, a1.z, a2.z), entry(a1.z, a2.z, a1.z, a2.z)};
}

/// The 2x2 tensor with eigenvalues 1 and gamma^2, the strong one at `angle`.
inline std::array<double, 3> tensor2(double gamma, double angle) {
  const double c = std::cos(angle), s = std::sin(angle), g2 = gamma * gamma;
  return {c * c + g2 * s * s, (1.0 - g2) * c * s, s * s + g2 * c * c};
}
inline double norm2(const std::array<double, 3>& g, double x, double y) {
  return std::sqrt(g[0] * x * x + 2.0 * g[1] * x * y + g[2] * y * y);
}

/// The curved, non-developable height field z = 0.5 sin(x) cos(y) over a
/// badly shaped 48 x 48 triangulation of [0, 2 pi]^2; flat = (x, y).
inline GeneratedSurface sineHeightField() {
  GeneratedSurface s = planeMesh(48, 48, 2.0 * kPi, 2.0 * kPi, 0.15, 0.6, false, 21);
  for (std::size_t v = 0; v < s.points.size(); ++v)
    s.points[v].z = 0.5 * std::sin(s.flat[v][0]) * std::cos(s.flat[v][1]);
  return s;
}

/// The vertex whose flat coordinates are nearest to (x, y).
inline VertexId nearestFlatVertex(const GeneratedSurface& s, double x, double y) {
  VertexId best = 0;
  for (VertexId v = 1; v < s.flat.size(); ++v)
    if (std::hypot(s.flat[v][0] - x, s.flat[v][1] - y) <
        std::hypot(s.flat[best][0] - x, s.flat[best][1] - y))
      best = v;
  return best;
}

/// A prism with n sides inscribed in the cylinder of radius r around the z
/// axis, m rows of height h each. flat = (unrolled arc position along the
/// prism's perimeter, z); the development is exact for the prism.
inline GeneratedSurface prismMesh(int n, int m, double r, double h, bool quads, std::uint32_t seed) {
  std::mt19937 rng(seed);
  GeneratedSurface s;
  const double side = 2.0 * r * std::sin(kPi / n);
  for (int j = 0; j <= m; ++j)
    for (int i = 0; i < n; ++i) {
      const double phi = 2.0 * kPi * i / n;
      s.points.push_back({r * std::cos(phi), r * std::sin(phi), h * j});
      s.flat.push_back({side * i, h * j});
    }
  auto id = [n](int i, int j) { return static_cast<VertexId>(j * n + (i % n)); };
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < n; ++i) {
      const VertexId a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      if (quads) {
        s.faces.add({a, b, c, d});
      } else if (rng() % 2) {
        s.faces.add({a, b, c});
        s.faces.add({a, c, d});
      } else {
        s.faces.add({a, b, d});
        s.faces.add({b, c, d});
      }
    }
  return s;
}

/// Distance in the unrolled prism between flat coordinates p and q, the
/// strip being periodic with the perimeter n * side.
inline double unrolledDistance(std::array<double, 2> p, std::array<double, 2> q, double perimeter,
                               double aroundFactor = 1.0, double alongFactor = 1.0) {
  double du = std::fmod(std::abs(p[0] - q[0]), perimeter);
  du = std::min(du, perimeter - du);
  return std::hypot(aroundFactor * du, alongFactor * (p[1] - q[1]));
}

/// Icosahedron subdivided `levels` times, projected onto the sphere of radius r.
inline GeneratedSurface icosphere(int levels, double r) {
  const double t = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3d> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                          {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<std::array<VertexId, 3>> tri = {
      {0, 11, 5}, {0, 5, 1}, {0, 1, 7}, {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
      {11, 10, 2}, {10, 7, 6}, {7, 1, 8}, {3, 9, 4}, {3, 4, 2}, {3, 2, 6}, {3, 6, 8},
      {3, 8, 9}, {4, 9, 5}, {2, 4, 11}, {6, 2, 10}, {8, 6, 7}, {9, 8, 1}};
  for (Vec3d& q : p) q = normalized(q);
  for (int l = 0; l < levels; ++l) {
    std::vector<std::array<VertexId, 3>> next;
    std::map<std::uint64_t, VertexId> mids;
    auto mid = [&](VertexId a, VertexId b) {
      const std::uint64_t key = (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
      const auto found = mids.find(key);
      if (found != mids.end()) return found->second;
      p.push_back(normalized(0.5 * (p[a] + p[b])));
      return mids[key] = static_cast<VertexId>(p.size() - 1);
    };
    for (const auto& f : tri) {
      const VertexId ab = mid(f[0], f[1]), bc = mid(f[1], f[2]), ca = mid(f[2], f[0]);
      next.push_back({f[0], ab, ca});
      next.push_back({f[1], bc, ab});
      next.push_back({f[2], ca, bc});
      next.push_back({ab, bc, ca});
    }
    tri = next;
  }
  GeneratedSurface s;
  for (const Vec3d& q : p) s.points.push_back(r * q);
  for (const auto& f : tri) s.faces.add({f[0], f[1], f[2]});
  return s;
}

/// Latitude-longitude sphere of radius r: `around` meridians, `rows` bands,
/// one vertex at each pole. The triangles at the poles are needles and the
/// quads of the bands (split along alternating diagonals) stretch towards
/// the poles: a badly shaped mesh of a smooth surface.
inline GeneratedSurface uvSphere(int around, int rows, double r) {
  GeneratedSurface s;
  s.points.push_back({0, 0, r});
  for (int j = 1; j < rows; ++j) {
    const double theta = kPi * j / rows;
    for (int i = 0; i < around; ++i) {
      const double phi = 2.0 * kPi * i / around;
      s.points.push_back({r * std::sin(theta) * std::cos(phi), r * std::sin(theta) * std::sin(phi),
                          r * std::cos(theta)});
    }
  }
  s.points.push_back({0, 0, -r});
  const VertexId south = static_cast<VertexId>(s.points.size() - 1);
  auto id = [around](int i, int j) { return static_cast<VertexId>(1 + (j - 1) * around + (i % around)); };
  for (int i = 0; i < around; ++i) s.faces.add({0, id(i, 1), id(i + 1, 1)});
  for (int j = 1; j + 1 < rows; ++j)
    for (int i = 0; i < around; ++i) {
      const VertexId a = id(i, j), b = id(i, j + 1), c = id(i + 1, j + 1), d = id(i + 1, j);
      if ((i + j) % 2) {
        s.faces.add({a, b, c});
        s.faces.add({a, c, d});
      } else {
        s.faces.add({a, b, d});
        s.faces.add({b, c, d});
      }
    }
  for (int i = 0; i < around; ++i) s.faces.add({south, id(i + 1, rows - 1), id(i, rows - 1)});
  return s;
}

}  // namespace stvd::test
