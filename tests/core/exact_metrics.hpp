// Metrics whose geodesic distances are known in closed form, for the
// accuracy specifications: a constant tensor (distance = the norm of the
// displacement), a constant Randers norm (the same, with a drift term) and
// the pull-back of the Euclidean metric through a smooth invertible map
// (distance = Euclidean distance of the images, wherever the straight
// segment between the images stays inside the image of the domain).
//
// Everything here is double precision and independent of the library's own
// arithmetic; only the conversion to stvd::SymTensor3 touches its types.
#pragma once

#include <array>
#include <cmath>

#include "stvd/voxel_grid/grid_geometry.hpp"
#include "stvd/types.hpp"

namespace stvd::test {

inline constexpr double kPi = 3.14159265358979323846;

/// A 3x3 matrix, row-major.
struct Mat3 {
  std::array<double, 9> a{1, 0, 0, 0, 1, 0, 0, 0, 1};

  double operator()(int r, int c) const { return a[3 * r + c]; }
  double& operator()(int r, int c) { return a[3 * r + c]; }
};

inline Mat3 operator*(const Mat3& p, const Mat3& q) {
  Mat3 m;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) m(r, c) = p(r, 0) * q(0, c) + p(r, 1) * q(1, c) + p(r, 2) * q(2, c);
  return m;
}
inline Vec3d operator*(const Mat3& m, Vec3d v) {
  return {m(0, 0) * v.x + m(0, 1) * v.y + m(0, 2) * v.z,
          m(1, 0) * v.x + m(1, 1) * v.y + m(1, 2) * v.z,
          m(2, 0) * v.x + m(2, 1) * v.y + m(2, 2) * v.z};
}
inline Mat3 transpose(const Mat3& m) {
  Mat3 t;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) t(r, c) = m(c, r);
  return t;
}
inline Vec3d normalized(Vec3d v) { return (1.0 / norm(v)) * v; }

/// Rotation by `angle` radians about `axis` (Rodrigues' formula).
inline Mat3 rotation(Vec3d axis, double angle) {
  const Vec3d u = normalized(axis);
  const double c = std::cos(angle), s = std::sin(angle), t = 1.0 - c;
  Mat3 m;
  m.a = {t * u.x * u.x + c,       t * u.x * u.y - s * u.z, t * u.x * u.z + s * u.y,
         t * u.x * u.y + s * u.z, t * u.y * u.y + c,       t * u.y * u.z - s * u.x,
         t * u.x * u.z - s * u.y, t * u.y * u.z + s * u.x, t * u.z * u.z + c};
  return m;
}

/// The symmetric matrix m in the library's storage order (m must be symmetric).
inline SymTensor3 toSymTensor(const Mat3& m) {
  return {static_cast<float>(m(0, 0)), static_cast<float>(m(0, 1)), static_cast<float>(m(0, 2)),
          static_cast<float>(m(1, 1)), static_cast<float>(m(1, 2)), static_cast<float>(m(2, 2))};
}

/// sqrt(v^T G v).
inline double tensorNorm(const Mat3& g, Vec3d v) { return std::sqrt(dot(v, g * v)); }

/// G = I + (gamma^2 - 1) d d^T for a unit direction d: vectors along d are
/// gamma times longer than under the Euclidean metric, vectors orthogonal to
/// d keep their length, so max ||v||_G/|v| over min ||v||_G/|v| is gamma.
inline Mat3 uniaxialTensor(double gamma, Vec3d direction) {
  const Vec3d d = normalized(direction);
  const double s = gamma * gamma - 1.0;
  Mat3 g;
  g.a = {1 + s * d.x * d.x, s * d.x * d.y,     s * d.x * d.z,
         s * d.y * d.x,     1 + s * d.y * d.y, s * d.y * d.z,
         s * d.z * d.x,     s * d.z * d.y,     1 + s * d.z * d.z};
  return g;
}

/// A grid whose index axes are the columns of `axes` (a rotation), with the
/// given spacing and origin.
inline GridGeometry orientedGrid(std::array<std::size_t, 3> size, std::array<double, 3> spacing,
                                 std::array<double, 3> origin, const Mat3& axes) {
  GridGeometry g;
  g.size = size;
  g.spacing = spacing;
  g.origin = origin;
  g.direction = axes.a;
  return g;
}

/// The constant Randers norm F(v) = sqrt(v^T M v) + omega^T v.
struct ExactRanders {
  Mat3 m;
  Vec3d omega;
  double operator()(Vec3d v) const { return tensorNorm(m, v) + dot(omega, v); }
};

/// phi(x) = S h(R (x - c)) with S = diag(gamma, 1, 1), a rotation R, and the
/// triangular map
///   h(u) = (u1 + a1 sin(w1 u2), u2, u3 + a3 sin(w3 u1)).
/// h has unit Jacobian determinant everywhere and the closed-form inverse
///   u2 = v2, u1 = v1 - a1 sin(w1 v2), u3 = v3 - a3 sin(w3 u1),
/// so phi is a global diffeomorphism of R^3. The pull-back metric
/// G(x) = J(x)^T J(x), J the Jacobian of phi, makes phi an isometry onto
/// (R^3, Euclidean): the geodesic distance in a domain B between x and y is
/// |phi(y) - phi(x)| whenever the straight segment phi(x) -> phi(y) lies in
/// phi(B).
struct TriangularPullbackMap {
  Mat3 r;
  Vec3d centre;
  double gamma = 1.0;
  double a1 = 0.0, w1 = 0.0, a3 = 0.0, w3 = 0.0;

  Vec3d operator()(Vec3d x) const {
    const Vec3d u = r * (x - centre);
    return {gamma * (u.x + a1 * std::sin(w1 * u.y)), u.y, u.z + a3 * std::sin(w3 * u.x)};
  }
  Vec3d inverse(Vec3d y) const {
    Vec3d u;
    u.y = y.y;
    u.x = y.x / gamma - a1 * std::sin(w1 * u.y);
    u.z = y.z - a3 * std::sin(w3 * u.x);
    return transpose(r) * u + centre;
  }
  Mat3 jacobian(Vec3d x) const {
    const Vec3d u = r * (x - centre);
    Mat3 sh;  // S times the Jacobian of h at u
    sh.a = {gamma, gamma * a1 * w1 * std::cos(w1 * u.y), 0.0,
            0.0,   1.0,                                  0.0,
            a3 * w3 * std::cos(w3 * u.x), 0.0,           1.0};
    return sh * r;
  }
  /// G(x) = J^T J.
  Mat3 metric(Vec3d x) const {
    const Mat3 j = jacobian(x);
    return transpose(j) * j;
  }
};

/// sqrt(lambda_max / lambda_min) of a symmetric positive-definite matrix:
/// the ratio of the longest to the shortest unit vector under its norm.
/// Eigenvalues from the trigonometric solution of the characteristic cubic.
inline double anisotropy(const Mat3& g) {
  const double p1 = g(0, 1) * g(0, 1) + g(0, 2) * g(0, 2) + g(1, 2) * g(1, 2);
  const double q = (g(0, 0) + g(1, 1) + g(2, 2)) / 3.0;
  const double p2 = (g(0, 0) - q) * (g(0, 0) - q) + (g(1, 1) - q) * (g(1, 1) - q) +
                    (g(2, 2) - q) * (g(2, 2) - q) + 2.0 * p1;
  const double p = std::sqrt(p2 / 6.0);
  if (p == 0.0) return 1.0;
  Mat3 b;
  for (int i = 0; i < 9; ++i) b.a[i] = (g.a[i] - (i % 4 == 0 ? q : 0.0)) / p;
  const double det = b(0, 0) * (b(1, 1) * b(2, 2) - b(1, 2) * b(2, 1)) -
                     b(0, 1) * (b(1, 0) * b(2, 2) - b(1, 2) * b(2, 0)) +
                     b(0, 2) * (b(1, 0) * b(2, 1) - b(1, 1) * b(2, 0));
  const double phi = std::acos(std::fmax(-1.0, std::fmin(1.0, det / 2.0))) / 3.0;
  const double largest = q + 2.0 * p * std::cos(phi);
  const double smallest = q + 2.0 * p * std::cos(phi + 2.0 * kPi / 3.0);
  return std::sqrt(largest / smallest);
}

}  // namespace stvd::test
