// Exact answers for FOD metrics (docs/fod.md, "STVD and Lanthier"): a
// constant FOD field of two crossing fibres, whose distance from a seed s
// is F*_exact(x - s), the convexified continuous norm, evaluated as the
// gauge of the hull of F's unit ball sampled along a very fine icosphere
// (and the FOD's refined maxima). Shared by tests/itk/fod_segment_norm_test.cpp
// and bench/fod_accuracy_table.cpp.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <map>
#include <numeric>
#include <tuple>
#include <vector>

#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/fod_field.hpp"
#include "stvd/imaging/spherical_harmonics.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::testing {

/// The two fibres of a crossing at `degrees`, in a plane tilted against
/// every grid axis (so that no fibre is a lattice direction of the grid).
inline void crossingFibres(double degrees, Vec3d fibre[2]) {
  const auto unit = [](Vec3d v) { return (1.0 / std::sqrt(dot(v, v))) * v; };
  const Vec3d e1 = unit({1.0, 0.35, 0.2});
  const Vec3d helper{0.1, 0.2, 1.0};
  const Vec3d e2 = unit(helper - dot(helper, e1) * e1);
  const double t = degrees * M_PI / 180.0;
  fibre[0] = e1;
  fibre[1] = std::cos(t) * e1 + std::sin(t) * e2;
}

/// Adds to 45 coefficients (lmax 8, MRtrix3's basis) a lobe along the LPS
/// direction d: h_l Y_lm(d), a function of u.d largest at d.
inline void addFodLobe(const imaging::FodField& f, float* c, const Vec3d& d) {
  const Vec3d s = f.toShFrame(d);
  const std::vector<double> y = imaging::evaluateShBasis(imaging::ShBasis::Tournier07, 8, s.x, s.y, s.z);
  for (int l = 0; l <= 8; l += 2)
    for (int m = -l; m <= l; ++m)
      c[l * (l + 1) / 2 + m] += static_cast<float>(std::exp(-0.02 * l * (l + 1)) * y[l * (l + 1) / 2 + m]);
}

/// A field whose every voxel holds the same two crossing fibres.
inline imaging::FodField constantCrossingField(const GridGeometry& geometry, double degrees) {
  imaging::FodField f;
  f.geometry = geometry;
  f.lmax = 8;
  f.basis = imaging::ShBasis::Tournier07;
  f.frame = imaging::FodFrame::Scanner;
  f.lpsToShFrame = imaging::lpsToFodFrame(imaging::FodFrame::Scanner, f.geometry);
  float c[45] = {};
  Vec3d fibre[2];
  crossingFibres(degrees, fibre);
  addFodLobe(f, c, fibre[0]);
  addFodLobe(f, c, fibre[1]);
  f.coefficients.resize(geometry.voxelCount() * 45);
  for (std::size_t v = 0; v < geometry.voxelCount(); ++v) std::copy(c, c + 45, f.coefficients.data() + 45 * v);
  return f;
}

/// F*_exact of one voxel's FOD: the gauge of the hull of its cost's unit
/// ball along icosphereDirections(subdivisions) (40962 directions for 6),
/// the 26 neighbour directions and its refined maxima; cached per primitive index offset of `geometry`.
class ExactFodNorm {
 public:
  ExactFodNorm(const imaging::FodField& field, int subdivisions, imaging::FodCostOptions options = {})
      : one_(oneVoxel(field)), geometry_(field.geometry) {
    // The fine icosphere holds the default one (and the 26 neighbour
    // directions are added as there): the methods' sampled hull lies
    // inside this one, so their F* is never below it but where the peaks'
    // refinement differs (1e-3 rad).
    const imaging::FodCostSampler sampler(one_, imaging::defaultFodSamplingDirections(field.geometry, subdivisions),
                                          options);
    sampler.unitBall(0, ball_);
  }
  const imaging::FodUnitBall& ball() const { return ball_; }
  /// F*_exact of a physical vector: the simplex method of convexHullGauge
  /// (big-M start, Dantzig's rule), but started from the previous query's
  /// optimal basis when that is feasible for this one (neighbouring queries
  /// cross the same facet); the optimum is proven by pricing every point.
  double operator()(const Vec3d& v) {
    if (v.x == 0.0 && v.y == 0.0 && v.z == 0.0) return 0.0;
    const Vec3d* w = ball_.points.data();
    const std::size_t n = ball_.points.size();
    const Vec3d artificial[3] = {{v.x < 0 ? -1.0 : 1.0, 0, 0}, {0, v.y < 0 ? -1.0 : 1.0, 0}, {0, 0, v.z < 0 ? -1.0 : 1.0}};
    const auto column = [&](std::size_t j) -> const Vec3d& { return j < n ? w[j] : artificial[j - n]; };
    const double bigM = 1e6;
    const auto cost = [&](std::size_t j) { return j < n ? 1.0 : bigM; };
    double inv[9], x[3];
    const auto solve = [&](const std::size_t* b) {
      if (!invertColumns(column(b[0]), column(b[1]), column(b[2]), inv)) return false;
      for (int r = 0; r < 3; ++r) x[r] = inv[3 * r] * v.x + inv[3 * r + 1] * v.y + inv[3 * r + 2] * v.z;
      return x[0] >= -1e-12 && x[1] >= -1e-12 && x[2] >= -1e-12;
    };
    std::size_t basis[3] = {basis_[0], basis_[1], basis_[2]};
    if (!(basis[0] < n && basis[1] < n && basis[2] < n && solve(basis))) {
      basis[0] = n, basis[1] = n + 1, basis[2] = n + 2;
      solve(basis);
    }
    for (int iteration = 0; iteration < 1000; ++iteration) {
      const double cb[3] = {cost(basis[0]), cost(basis[1]), cost(basis[2])};
      const Vec3d y{inv[0] * cb[0] + inv[3] * cb[1] + inv[6] * cb[2], inv[1] * cb[0] + inv[4] * cb[1] + inv[7] * cb[2],
                    inv[2] * cb[0] + inv[5] * cb[1] + inv[8] * cb[2]};
      std::size_t entering = n;
      double best = -1e-12 * (1.0 + std::sqrt(dot(y, y)));
      for (std::size_t j = 0; j < n; ++j) {
        const double r = 1.0 - dot(y, w[j]);
        if (r < best) best = r, entering = j;
      }
      if (entering == n) {
        if (basis[0] >= n || basis[1] >= n || basis[2] >= n) break;  // an artificial column left: fall back
        std::copy(basis, basis + 3, basis_);
        return std::max(0.0, x[0]) + std::max(0.0, x[1]) + std::max(0.0, x[2]);
      }
      const Vec3d& a = w[entering];
      const double d[3] = {inv[0] * a.x + inv[1] * a.y + inv[2] * a.z, inv[3] * a.x + inv[4] * a.y + inv[5] * a.z,
                           inv[6] * a.x + inv[7] * a.y + inv[8] * a.z};
      int leaving = -1;
      double ratio = 1e300;
      for (int k = 0; k < 3; ++k)
        if (d[k] > 1e-14) {
          const double r = std::max(0.0, x[k]) / d[k];
          if (r < ratio || (r == ratio && basis[k] >= n)) ratio = r, leaving = k;
        }
      if (leaving < 0) break;
      basis[leaving] = entering;
      solve(basis);
    }
    basis_[0] = n;
    return imaging::convexHullGauge(w, n, v);
  }
  /// F*_exact of the physical vector of the index offset (di, dj, dk).
  double ofOffset(int di, int dj, int dk) {
    const int g = std::gcd(std::gcd(std::abs(di), std::abs(dj)), std::abs(dk));
    if (g == 0) return 0.0;
    std::tuple<int, int, int> key{di / g, dj / g, dk / g};
    auto it = cache_.find(key);
    if (it == cache_.end()) {
      // F* is symmetric: the opposite offset's value serves.
      auto other = cache_.find({-di / g, -dj / g, -dk / g});
      const double value = other != cache_.end()
                               ? other->second
                               : (*this)(geometry_.indexToPhysicalOffset(di / g, dj / g, dk / g));
      it = cache_.emplace(key, value).first;
    }
    return g * it->second;
  }

 private:
  static bool invertColumns(const Vec3d& a, const Vec3d& b, const Vec3d& c, double inv[9]) {
    const Vec3d r0{b.y * c.z - b.z * c.y, b.z * c.x - b.x * c.z, b.x * c.y - b.y * c.x};
    const Vec3d r1{c.y * a.z - c.z * a.y, c.z * a.x - c.x * a.z, c.x * a.y - c.y * a.x};
    const Vec3d r2{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
    const double det = dot(a, r0);
    if (!(std::abs(det) > 1e-300)) return false;
    const Vec3d rows[3] = {r0, r1, r2};
    for (int r = 0; r < 3; ++r) inv[3 * r] = rows[r].x / det, inv[3 * r + 1] = rows[r].y / det, inv[3 * r + 2] = rows[r].z / det;
    return true;
  }
  static imaging::FodField oneVoxel(const imaging::FodField& field) {
    imaging::FodField one = field;
    one.geometry.size = {1, 1, 1};
    one.coefficients.assign(field.coefficients.begin(), field.coefficients.begin() + field.coefficientCount());
    return one;
  }
  imaging::FodField one_;
  GridGeometry geometry_;
  imaging::FodUnitBall ball_;
  std::map<std::tuple<int, int, int>, double> cache_;
  std::size_t basis_[3] = {0, 0, 0};  // an optimal basis of the last query (points only)
};

}  // namespace stvd::testing
