#include "stvd/imaging/fod_cost.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "stvd/imaging/spherical_harmonics.hpp"
#include "stvd/imaging/tensor_frames.hpp"

namespace stvd::imaging {

void FodCostOptions::validate() const {
  if (!(floor > 0.0 && floor <= 1.0))
    throw std::invalid_argument("FOD cost: the floor must be in (0, 1], not " + std::to_string(floor));
  if (!(power > 0.0 && power <= 8.0))
    throw std::invalid_argument("FOD cost: the power must be in (0, 8], not " + std::to_string(power));
}

namespace {

Vec3d normalised(const Vec3d& v) {
  const double n = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return {v.x / n, v.y / n, v.z / n};
}

/// sum_j y_j c_j in four interleaved partial sums (j mod 4), added at the
/// end: four chains of additions instead of one (the caps' amplitudes, one
/// row at a time); the fast ball and its reference both sum so.
double capDot(const double* y, const double* c, int count) {
  double s[4] = {0.0, 0.0, 0.0, 0.0};
  int j = 0;
  for (; j + 4 <= count; j += 4)
    for (int q = 0; q < 4; ++q) s[q] += y[j + q] * c[j + q];
  for (; j < count; ++j) s[j % 4] += y[j] * c[j];
  return (s[0] + s[1]) + (s[2] + s[3]);
}

}  // namespace

std::vector<Vec3d> icosphereDirections(int subdivisions) {
  if (subdivisions < 0 || subdivisions > 6)
    throw std::invalid_argument("icosphere: subdivisions must be 0 to 6, not " + std::to_string(subdivisions));
  const double p = (1.0 + std::sqrt(5.0)) / 2.0;
  std::vector<Vec3d> v = {{-1, p, 0}, {1, p, 0}, {-1, -p, 0}, {1, -p, 0}, {0, -1, p}, {0, 1, p},
                          {0, -1, -p}, {0, 1, -p}, {p, 0, -1}, {p, 0, 1}, {-p, 0, -1}, {-p, 0, 1}};
  for (Vec3d& x : v) x = normalised(x);
  std::vector<std::array<int, 3>> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                           {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                           {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                           {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (int s = 0; s < subdivisions; ++s) {
    std::map<std::pair<int, int>, int> midpoint;
    auto middle = [&](int a, int b) {
      const std::pair<int, int> key{std::min(a, b), std::max(a, b)};
      auto it = midpoint.find(key);
      if (it != midpoint.end()) return it->second;
      v.push_back(normalised(v[a] + v[b]));
      const int index = static_cast<int>(v.size()) - 1;
      midpoint.emplace(key, index);
      return index;
    };
    std::vector<std::array<int, 3>> next;
    next.reserve(faces.size() * 4);
    for (const auto& f : faces) {
      const int a = middle(f[0], f[1]), b = middle(f[1], f[2]), c = middle(f[2], f[0]);
      next.push_back({f[0], a, c});
      next.push_back({f[1], b, a});
      next.push_back({f[2], c, b});
      next.push_back({a, b, c});
    }
    faces = std::move(next);
  }
  return v;
}

std::vector<Vec3d> neighbourDirections26(const GridGeometry& geometry) {
  std::vector<Vec3d> d;
  for (int k = -1; k <= 1; ++k)
    for (int j = -1; j <= 1; ++j)
      for (int i = -1; i <= 1; ++i)
        if (i || j || k) d.push_back(normalised(geometry.indexToPhysicalOffset(i, j, k)));
  return d;
}

std::vector<Vec3d> defaultFodSamplingDirections(const GridGeometry& geometry, int subdivisions) {
  // The icosphere turned with the grid's axes: the same directions relative
  // to the voxels whatever the image's rotation, as the 26 neighbours are.
  std::vector<Vec3d> d = icosphereDirections(subdivisions);
  const Matrix3 axes = voxelAxes(geometry);  // columns: the unit index axes in LPS
  for (Vec3d& g : d)
    g = normalised({axes[0] * g.x + axes[1] * g.y + axes[2] * g.z, axes[3] * g.x + axes[4] * g.y + axes[5] * g.z,
                    axes[6] * g.x + axes[7] * g.y + axes[8] * g.z});
  const std::vector<Vec3d> n = neighbourDirections26(geometry);
  d.insert(d.end(), n.begin(), n.end());
  return d;
}

FodSampling adaptiveFodSampling(const GridGeometry& geometry, int coarse, int dense, double capRadiusDegrees) {
  if (!(capRadiusDegrees > 0.0 && capRadiusDegrees <= 90.0))
    throw std::invalid_argument("FOD sampling: the caps' radius must be in (0, 90] degrees, not " +
                                std::to_string(capRadiusDegrees));
  FodSampling s;
  s.directions = defaultFodSamplingDirections(geometry, coarse);
  // The dense icosphere turned with the grid as the coarse one is (its
  // first vertices are the coarse icosphere's: the sampler drops those).
  std::vector<Vec3d> d = icosphereDirections(dense);
  const Matrix3 axes = voxelAxes(geometry);
  for (Vec3d& g : d)
    g = normalised({axes[0] * g.x + axes[1] * g.y + axes[2] * g.z, axes[3] * g.x + axes[4] * g.y + axes[5] * g.z,
                    axes[6] * g.x + axes[7] * g.y + axes[8] * g.z});
  s.caps.directions = std::move(d);
  s.caps.radius = capRadiusDegrees * M_PI / 180.0;
  return s;
}

FodCostSampler::FodCostSampler(const FodField& field, std::vector<Vec3d> directions, FodCostOptions options,
                               FodPeakCaps caps)
    : field_(field), directions_(std::move(directions)), options_(options) {
  options_.validate();
  const Matrix3 axes = voxelAxes(field.geometry);
  axisI_ = {axes[0], axes[3], axes[6]};
  axisJ_ = {axes[1], axes[4], axes[7]};
  if (directions_.size() < 4) throw std::invalid_argument("FOD cost: at least 4 sampling directions are needed");
  const int count = field.coefficientCount();
  basis_.resize(directions_.size() * static_cast<std::size_t>(count));
  for (std::size_t i = 0; i < directions_.size(); ++i) {
    const Vec3d s = field.toShFrame(directions_[i]);
    directions_[i] = normalised(directions_[i]);
    evaluateShBasis(field.basis, field.lmax, s.x, s.y, s.z, basis_.data() + i * count);
  }
  // The neighbours of each direction for finding the FOD's maxima: those
  // within 1.5 typical spacings (the spacing of N even directions).
  spacing_ = std::sqrt(4.0 * M_PI / static_cast<double>(directions_.size()));
  const double within = std::cos(std::min(M_PI / 2, 1.5 * spacing_));
  neighbours_.resize(directions_.size());
  for (std::size_t i = 0; i < directions_.size(); ++i)
    for (std::size_t j = 0; j < directions_.size(); ++j)
      if (j != i && dot(directions_[i], directions_[j]) >= within) neighbours_[i].push_back(static_cast<int>(j));

  // The fast unit ball (unitBall). An FOD is even, so a direction and its
  // opposite have one amplitude: one row of the basis per direction up to
  // sign (the first of them; the icosphere and the 26 neighbours hold every
  // direction with its opposite), stored coefficient by coefficient so that
  // the amplitudes of all rows are one vectorisable pass per coefficient.
  const std::size_t n = directions_.size();
  twin_.assign(n, -1);
  rowOf_.assign(n, 0);
  std::vector<std::size_t> rowDirection;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3d& g = directions_[i];
    for (std::size_t j = 0; j < i && twin_[i] < 0; ++j) {
      const Vec3d& h = directions_[j];
      if ((g.x == h.x && g.y == h.y && g.z == h.z) || (g.x == -h.x && g.y == -h.y && g.z == -h.z))
        twin_[i] = static_cast<int>(j);
    }
    if (twin_[i] >= 0) {
      rowOf_[i] = rowOf_[static_cast<std::size_t>(twin_[i])];
    } else {
      rowOf_[i] = static_cast<int>(rowDirection.size());
      rowDirection.push_back(i);
    }
  }
  rows_ = rowDirection.size();
  neighbourRows_.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    for (int j : neighbours_[i]) neighbourRows_[i].push_back(rowOf_[static_cast<std::size_t>(j)]);
  basisByCoefficient_.resize(static_cast<std::size_t>(count) * rows_);
  for (std::size_t r = 0; r < rows_; ++r)
    for (int j = 0; j < count; ++j)
      basisByCoefficient_[static_cast<std::size_t>(j) * rows_ + r] = basis_[rowDirection[r] * count + j];
  // The caps: the dense directions that are neither a sampling direction
  // nor the opposite of one (those points are in the ball already).
  if (!caps.directions.empty() && caps.radius > 0.0) {
    if (!(caps.radius <= M_PI / 2))
      throw std::invalid_argument("FOD cost: the caps' radius must be at most 90 degrees");
    capRadius_ = caps.radius;
    capCos_ = std::cos(caps.radius);
    for (const Vec3d& raw : caps.directions) {
      const Vec3d d = normalised(raw);
      bool known = false;
      for (std::size_t i = 0; i < n && !known; ++i) known = std::abs(dot(d, directions_[i])) > 1.0 - 1e-12;
      if (!known) capDirections_.push_back(d);
    }
    capBasis_.resize(capDirections_.size() * static_cast<std::size_t>(count));
    for (std::size_t i = 0; i < capDirections_.size(); ++i) {
      const Vec3d s = field.toShFrame(capDirections_[i]);
      evaluateShBasis(field.basis, field.lmax, s.x, s.y, s.z, capBasis_.data() + i * count);
    }
    // One row per direction up to sign (the first of a pair).
    std::vector<unsigned char> paired(capDirections_.size(), 0);
    for (std::size_t i = 0; i < capDirections_.size(); ++i) {
      if (paired[i]) continue;
      capRowDirection_.push_back(static_cast<int>(i));
      for (std::size_t j = i + 1; j < capDirections_.size(); ++j)
        if (!paired[j] && dot(capDirections_[i], capDirections_[j]) < -1.0 + 1e-12) {
          paired[j] = 1;
          break;
        }
    }
    capRows_ = capRowDirection_.size();
    capSpacing_ = std::sqrt(4.0 * M_PI / static_cast<double>(directionCount()));
    nearCos_ = std::cos(std::min(M_PI / 2, spacing_));
    capRowBasis_.resize(capRows_ * static_cast<std::size_t>(count));
    for (std::size_t r = 0; r < capRows_; ++r)
      std::copy(capBasis_.begin() + static_cast<std::ptrdiff_t>(capRowDirection_[r]) * count,
                capBasis_.begin() + static_cast<std::ptrdiff_t>(capRowDirection_[r] + 1) * count,
                capRowBasis_.begin() + static_cast<std::ptrdiff_t>(r * count));
  }
}

namespace {

/// The factors of the Legendre recurrences, as evaluateShBasis has them.
struct LegendreFactors {
  static constexpr int L = kMaxShDegree;
  double diagonal[L + 1], subdiagonal[L + 1], a[L + 1][L + 1], b[L + 1][L + 1];
  LegendreFactors() : diagonal{}, subdiagonal{}, a{}, b{} {
    for (int m = 1; m <= L; ++m) diagonal[m] = -std::sqrt((2.0 * m + 1.0) / (2.0 * m));
    for (int m = 0; m < L; ++m) subdiagonal[m] = std::sqrt(2.0 * m + 3.0);
    for (int m = 0; m <= L; ++m)
      for (int l = m + 2; l <= L; ++l) {
        a[l][m] = std::sqrt((4.0 * l * l - 1.0) / (double(l) * l - double(m) * m));
        b[l][m] = std::sqrt((double(l - 1) * (l - 1) - double(m) * m) / (4.0 * (l - 1) * (l - 1) - 1.0));
      }
  }
};

/// sum_j Y_j(x, y, z) c_j: the products and their order of
/// evaluateShBasis followed by a dot product with c, bit for bit, without
/// the array of functions (the hot loop of the maxima's refinement).
template <ShBasis B>
double shExpansion(int lmax, double x, double y, double z, const float* c) {
  static const LegendreFactors f;
  constexpr int L = kMaxShDegree;
  const double r = std::sqrt(x * x + y * y + z * z);
  const double ct = std::clamp(z / r, -1.0, 1.0);
  const double st = std::sqrt(std::max(0.0, 1.0 - ct * ct));
  double p[L + 1][L + 1];
  p[0][0] = 0.5 / std::sqrt(M_PI);
  for (int m = 1; m <= lmax; ++m) p[m][m] = f.diagonal[m] * st * p[m - 1][m - 1];
  for (int m = 0; m < lmax; ++m) p[m + 1][m] = f.subdiagonal[m] * ct * p[m][m];
  for (int m = 0; m <= lmax; ++m)
    for (int l = m + 2; l <= lmax; ++l) p[l][m] = f.a[l][m] * (ct * p[l - 1][m] - f.b[l][m] * p[l - 2][m]);
  double cosm[L + 1], sinm[L + 1];
  const double rxy = std::sqrt(x * x + y * y);
  const double c1 = rxy > 0.0 ? x / rxy : 1.0, s1 = rxy > 0.0 ? y / rxy : 0.0;
  cosm[0] = 1.0;
  sinm[0] = 0.0;
  for (int m = 1; m <= lmax; ++m) {
    cosm[m] = cosm[m - 1] * c1 - sinm[m - 1] * s1;
    sinm[m] = sinm[m - 1] * c1 + cosm[m - 1] * s1;
  }
  const double s2 = B == ShBasis::Tournier07Legacy ? 1.0 : std::sqrt(2.0);
  double sum = 0.0;
  for (int l = 0; l <= lmax; l += 2) {
    const int centre = l * (l + 1) / 2;
    for (int m = l; m >= 1; --m) {  // j = centre - m
      const double k = s2 * p[l][m];
      double value;
      if constexpr (B == ShBasis::Tournier07 || B == ShBasis::Tournier07Legacy)
        value = k * sinm[m];
      else if constexpr (B == ShBasis::Descoteaux07)
        value = (m % 2 ? -1.0 : 1.0) * k * cosm[m];
      else
        value = k * cosm[m];
      sum += value * c[centre - m];
    }
    sum += p[l][0] * c[centre];
    for (int m = 1; m <= l; ++m) {  // j = centre + m
      const double k = s2 * p[l][m];
      const double value = B == ShBasis::Tournier07 || B == ShBasis::Tournier07Legacy ? k * cosm[m] : k * sinm[m];
      sum += value * c[centre + m];
    }
  }
  return sum;
}

/// shExpansion at four directions at once, lane by lane the same
/// operations in the same order (so the same bits), in loops over the lanes
/// that the compiler vectorises: the four steps of one move of the maxima's
/// pattern search.
template <ShBasis B>
void shExpansion4(int lmax, const double (&x)[4], const double (&y)[4], const double (&z)[4], const float* c,
                  double (&out)[4]) {
  static const LegendreFactors f;
  constexpr int L = kMaxShDegree;
  double ct[4], st[4], c1[4], s1[4];
  for (int q = 0; q < 4; ++q) {
    const double r = std::sqrt(x[q] * x[q] + y[q] * y[q] + z[q] * z[q]);
    ct[q] = std::clamp(z[q] / r, -1.0, 1.0);
    st[q] = std::sqrt(std::max(0.0, 1.0 - ct[q] * ct[q]));
    const double rxy = std::sqrt(x[q] * x[q] + y[q] * y[q]);
    c1[q] = rxy > 0.0 ? x[q] / rxy : 1.0;
    s1[q] = rxy > 0.0 ? y[q] / rxy : 0.0;
  }
  double p[L + 1][L + 1][4];
  for (int q = 0; q < 4; ++q) p[0][0][q] = 0.5 / std::sqrt(M_PI);
  for (int m = 1; m <= lmax; ++m)
    for (int q = 0; q < 4; ++q) p[m][m][q] = f.diagonal[m] * st[q] * p[m - 1][m - 1][q];
  for (int m = 0; m < lmax; ++m)
    for (int q = 0; q < 4; ++q) p[m + 1][m][q] = f.subdiagonal[m] * ct[q] * p[m][m][q];
  for (int m = 0; m <= lmax; ++m)
    for (int l = m + 2; l <= lmax; ++l)
      for (int q = 0; q < 4; ++q) p[l][m][q] = f.a[l][m] * (ct[q] * p[l - 1][m][q] - f.b[l][m] * p[l - 2][m][q]);
  double cosm[L + 1][4], sinm[L + 1][4];
  for (int q = 0; q < 4; ++q) {
    cosm[0][q] = 1.0;
    sinm[0][q] = 0.0;
  }
  for (int m = 1; m <= lmax; ++m)
    for (int q = 0; q < 4; ++q) {
      cosm[m][q] = cosm[m - 1][q] * c1[q] - sinm[m - 1][q] * s1[q];
      sinm[m][q] = sinm[m - 1][q] * c1[q] + cosm[m - 1][q] * s1[q];
    }
  const double s2 = B == ShBasis::Tournier07Legacy ? 1.0 : std::sqrt(2.0);
  double sum[4] = {0.0, 0.0, 0.0, 0.0};
  for (int l = 0; l <= lmax; l += 2) {
    const int centre = l * (l + 1) / 2;
    for (int m = l; m >= 1; --m) {
      const double cj = c[centre - m];
      for (int q = 0; q < 4; ++q) {
        const double k = s2 * p[l][m][q];
        double value;
        if constexpr (B == ShBasis::Tournier07 || B == ShBasis::Tournier07Legacy)
          value = k * sinm[m][q];
        else if constexpr (B == ShBasis::Descoteaux07)
          value = (m % 2 ? -1.0 : 1.0) * k * cosm[m][q];
        else
          value = k * cosm[m][q];
        sum[q] += value * cj;
      }
    }
    const double c0 = c[centre];
    for (int q = 0; q < 4; ++q) sum[q] += p[l][0][q] * c0;
    for (int m = 1; m <= l; ++m) {
      const double cj = c[centre + m];
      for (int q = 0; q < 4; ++q) {
        const double k = s2 * p[l][m][q];
        const double value =
            B == ShBasis::Tournier07 || B == ShBasis::Tournier07Legacy ? k * cosm[m][q] : k * sinm[m][q];
        sum[q] += value * cj;
      }
    }
  }
  for (int q = 0; q < 4; ++q) out[q] = sum[q];
}

}  // namespace

void FodCostSampler::amplitudesAt4(const float* c, const Vec3d (&unitLps)[4], double (&out)[4]) const {
  double x[4], y[4], z[4];
  for (int q = 0; q < 4; ++q) {
    const Vec3d s = field_.toShFrame(unitLps[q]);
    x[q] = s.x;
    y[q] = s.y;
    z[q] = s.z;
  }
  switch (field_.basis) {
    case ShBasis::Tournier07:
      return shExpansion4<ShBasis::Tournier07>(field_.lmax, x, y, z, c, out);
    case ShBasis::Tournier07Legacy:
      return shExpansion4<ShBasis::Tournier07Legacy>(field_.lmax, x, y, z, c, out);
    case ShBasis::Descoteaux07:
      return shExpansion4<ShBasis::Descoteaux07>(field_.lmax, x, y, z, c, out);
    case ShBasis::Descoteaux07Legacy:
      break;
  }
  shExpansion4<ShBasis::Descoteaux07Legacy>(field_.lmax, x, y, z, c, out);
}

double FodCostSampler::amplitudeAt(const float* c, const Vec3d& unitLps, bool simple) const {
  const Vec3d s = field_.toShFrame(unitLps);
  if (simple) {
    double y[91];
    evaluateShBasis(field_.basis, field_.lmax, s.x, s.y, s.z, y);
    double a = 0.0;
    for (int j = 0, n = field_.coefficientCount(); j < n; ++j) a += y[j] * c[j];
    return a;
  }
  switch (field_.basis) {
    case ShBasis::Tournier07:
      return shExpansion<ShBasis::Tournier07>(field_.lmax, s.x, s.y, s.z, c);
    case ShBasis::Tournier07Legacy:
      return shExpansion<ShBasis::Tournier07Legacy>(field_.lmax, s.x, s.y, s.z, c);
    case ShBasis::Descoteaux07:
      return shExpansion<ShBasis::Descoteaux07>(field_.lmax, s.x, s.y, s.z, c);
    case ShBasis::Descoteaux07Legacy:
      break;
  }
  return shExpansion<ShBasis::Descoteaux07Legacy>(field_.lmax, s.x, s.y, s.z, c);
}

Vec3d FodCostSampler::refinePeak(const float* c, Vec3d u, double step, double* amplitude, bool simple) const {
  // A pattern search on the sphere: steps along two tangent directions,
  // halved when none improves, from half a spacing down to 1e-3 rad (0.06
  // degrees; F* = F = 1 at the point found, however precise).
  double best = amplitudeAt(c, u, simple);
  while (step > 1e-3) {
    // Tangents from the grid's axes (not LPS's), so that the search turns
    // with the image as the sampling directions do.
    const Vec3d helper = std::abs(dot(u, axisI_)) < 0.9 ? axisI_ : axisJ_;
    const Vec3d t1 = normalised(helper - dot(helper, u) * u);
    const Vec3d t2{u.y * t1.z - u.z * t1.y, u.z * t1.x - u.x * t1.z, u.x * t1.y - u.y * t1.x};
    Vec3d next = u;
    double nextValue = best;
    const Vec3d candidates[4] = {normalised(u + step * t1), normalised(u + step * (-1.0 * t1)),
                                 normalised(u + step * t2), normalised(u + step * (-1.0 * t2))};
    double values[4];
    if (simple)
      for (int q = 0; q < 4; ++q) values[q] = amplitudeAt(c, candidates[q], true);
    else
      amplitudesAt4(c, candidates, values);
    for (int q = 0; q < 4; ++q)
      if (values[q] > nextValue) {
        nextValue = values[q];
        next = candidates[q];
      }
    if (nextValue > best) {
      best = nextValue;
      u = next;
    } else {
      step *= 0.5;
    }
  }
  *amplitude = best;
  return u;
}

void FodCostSampler::unitBallReference(std::size_t v, FodUnitBall& ball) const {
  const int count = field_.coefficientCount();
  const float* c = field_.voxelCoefficients(v);
  const std::size_t n = directions_.size();
  std::vector<double> a(n);
  double amax = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) {
    const double* y = basis_.data() + i * count;
    double s = 0.0;
    for (int j = 0; j < count; ++j) s += y[j] * c[j];
    a[i] = s;
    amax = std::max(amax, s);
  }
  ball.peaks.clear();
  ball.points.resize(n);
  const double lowest = std::pow(options_.floor, options_.power);
  if (!(amax > 0.0)) {
    ball.amplitudeMax = amax;
    for (std::size_t i = 0; i < n; ++i) ball.points[i] = lowest * directions_[i];
    return;
  }
  // The local maxima over the sampling directions, refined; with caps,
  // each from the best of its cap's directions within a spacing, by steps
  // from half the caps' spacing.
  std::vector<double> peakValues;
  std::vector<Vec3d> centres;
  double coefficients[91];
  for (int j = 0; j < count; ++j) coefficients[j] = c[j];
  auto capAmplitude = [&](std::size_t d) { return capDot(capBasis_.data() + d * count, coefficients, count); };
  for (std::size_t i = 0; i < n; ++i) {
    if (a[i] < options_.floor * amax) continue;
    bool isMax = true;
    for (int j : neighbours_[i]) isMax = isMax && a[i] >= a[j];
    if (!isMax) continue;
    double value = 0.0;
    Vec3d start = directions_[i];
    double step = 0.5 * spacing_;
    if (!capDirections_.empty()) {
      centres.push_back(directions_[i]);
      double best = a[i];
      for (std::size_t d = 0; d < capDirections_.size(); ++d)
        if (dot(directions_[i], capDirections_[d]) >= nearCos_) {
          const double s = capAmplitude(d);
          if (s > best) {
            best = s;
            start = capDirections_[d];
          }
        }
      step = 0.5 * capSpacing_;
    }
    ball.peaks.push_back(refinePeak(c, start, step, &value, true));
    peakValues.push_back(value);
    amax = std::max(amax, value);
  }
  ball.amplitudeMax = amax;
  for (std::size_t i = 0; i < n; ++i)
    ball.points[i] = std::pow(std::max(options_.floor, std::min(1.0, a[i] / amax)), options_.power) * directions_[i];
  for (std::size_t k = 0; k < ball.peaks.size(); ++k)
    ball.points.push_back(std::pow(std::max(options_.floor, std::min(1.0, peakValues[k] / amax)), options_.power) *
                          ball.peaks[k]);
  // The caps: every dense direction within the radius of a maximum (the
  // sampling direction it was found at) whose amplitude is above the floor.
  for (std::size_t d = 0; d < capDirections_.size(); ++d) {
    bool near = false;
    for (const Vec3d& p : centres) near = near || dot(p, capDirections_[d]) >= capCos_;
    if (!near) continue;
    const double s = capAmplitude(d);
    if (s > options_.floor * amax)
      ball.points.push_back(std::pow(std::min(1.0, s / amax), options_.power) * capDirections_[d]);
  }
}

void FodCostSampler::unitBall(std::size_t v, FodUnitBall& ball) const {
  // What unitBallReference computes, faster: the amplitudes one row per
  // direction up to sign; a maximum whose opposite (or duplicate) was
  // refined already is that one's point turned round (an FOD is even), so
  // each antipodal pair of maxima is refined once, its four trial steps
  // evaluated at once; the power skipped when it is 1.
  const int count = field_.coefficientCount();
  const float* c = field_.voxelCoefficients(v);
  const std::size_t n = directions_.size();
  std::vector<double>& row = ball.rowAmplitudes;
  row.assign(rows_, 0.0);
  for (int j = 0; j < count; ++j) {
    const double cj = c[j];
    const double* y = basisByCoefficient_.data() + static_cast<std::size_t>(j) * rows_;
    double* out = row.data();
    for (std::size_t r = 0; r < rows_; ++r) out[r] += y[r] * cj;
  }
  double amax = -std::numeric_limits<double>::infinity();
  for (std::size_t r = 0; r < rows_; ++r) amax = std::max(amax, row[r]);
  auto amplitude = [&](std::size_t i) { return row[static_cast<std::size_t>(rowOf_[i])]; };
  ball.peaks.clear();
  ball.points.resize(n);
  const double lowest = std::pow(options_.floor, options_.power);
  if (!(amax > 0.0)) {
    ball.amplitudeMax = amax;
    for (std::size_t i = 0; i < n; ++i) ball.points[i] = lowest * directions_[i];
    return;
  }
  std::vector<double>& peakValues = ball.peakValues;
  std::vector<int>& peakOf = ball.peakOfDirection;
  peakValues.clear();
  peakOf.assign(n, -1);
  ball.capTaken.clear();
  double coefficients[91];  // the coefficients as doubles, for the caps
  bool coefficientsAsDouble = false;
  const double least0 = options_.floor * amax;
  for (std::size_t i = 0; i < n; ++i) {
    const double ai = amplitude(i);
    if (ai < least0) continue;
    bool isMax = true;
    for (int r : neighbourRows_[i])
      if (!(ai >= row[static_cast<std::size_t>(r)])) {
        isMax = false;
        break;
      }
    if (!isMax) continue;
    const int twin = twin_[i];
    if (twin >= 0 && peakOf[static_cast<std::size_t>(twin)] >= 0) {
      const std::size_t k = static_cast<std::size_t>(peakOf[static_cast<std::size_t>(twin)]);
      const bool same = dot(directions_[i], directions_[static_cast<std::size_t>(twin)]) > 0.0;
      ball.peaks.push_back(same ? ball.peaks[k] : -1.0 * ball.peaks[k]);
      peakValues.push_back(peakValues[k]);
    } else {
      Vec3d start = directions_[i];
      double step = 0.5 * spacing_;
      if (capRows_ > 0) {
        // The cap's rows around this maximum (and its opposite: |cos|),
        // each amplitude once; the refinement starts from the best of them
        // within a spacing.
        const Vec3d g = directions_[i];
        if (!coefficientsAsDouble) {
          for (int j = 0; j < count; ++j) coefficients[j] = c[j];
          coefficientsAsDouble = true;
        }
        if (ball.capSeen.size() != capRows_) {
          ball.capSeen.assign(capRows_, 0);
          ball.capAmplitudes.assign(capRows_, 0.0);
        }
        double best = ai;
        for (std::size_t r = 0; r < capRows_; ++r) {
          const Vec3d& d = capDirections_[static_cast<std::size_t>(capRowDirection_[r])];
          const double cd = dot(g, d), acd = std::abs(cd);
          if (!(acd >= capCos_)) continue;
          if (!ball.capSeen[r]) {
            ball.capSeen[r] = 1;
            ball.capTaken.push_back(static_cast<int>(r));
            ball.capAmplitudes[r] = capDot(capRowBasis_.data() + r * static_cast<std::size_t>(count), coefficients, count);
          }
          if (acd >= nearCos_ && ball.capAmplitudes[r] > best) {
            best = ball.capAmplitudes[r];
            start = cd > 0.0 ? d : -1.0 * d;
          }
        }
        step = 0.5 * capSpacing_;
      }
      double value = 0.0;
      ball.peaks.push_back(refinePeak(c, start, step, &value, false));
      peakValues.push_back(value);
      amax = std::max(amax, value);
    }
    peakOf[i] = static_cast<int>(ball.peaks.size()) - 1;
  }
  ball.amplitudeMax = amax;
  const bool linear = options_.power == 1.0;
  auto radius = [&](double a) {
    const double r = std::max(options_.floor, std::min(1.0, a / amax));
    return linear ? r : std::pow(r, options_.power);
  };
  for (std::size_t i = 0; i < n; ++i) ball.points[i] = radius(amplitude(i)) * directions_[i];
  for (std::size_t k = 0; k < ball.peaks.size(); ++k) ball.points.push_back(radius(peakValues[k]) * ball.peaks[k]);
  const double least = options_.floor * amax;
  for (std::size_t t = 0; t < ball.capTaken.size(); ++t) {
    const std::size_t r = static_cast<std::size_t>(ball.capTaken[t]);
    ball.capSeen[r] = 0;  // ready for the next voxel
    if (!(ball.capAmplitudes[r] > least)) continue;  // on the floor's sphere
    const Vec3d w = radius(ball.capAmplitudes[r]) * capDirections_[static_cast<std::size_t>(capRowDirection_[r])];
    ball.points.push_back(w);
    ball.points.push_back(-1.0 * w);
  }
}

double FodCostSampler::cost(std::size_t v, const Vec3d& d, double amplitudeMax) const {
  const double length = std::sqrt(dot(d, d));
  const double lowest = std::pow(options_.floor, options_.power);
  if (!(amplitudeMax > 0.0)) return length / lowest;
  const double a = field_.amplitude(v, d);
  return length / std::pow(std::max(options_.floor, std::min(1.0, a / amplitudeMax)), options_.power);
}

namespace {

/// The inverse of the 3x3 matrix whose columns are a, b, c (row-major), or
/// false when it is singular.
bool invertColumns(const Vec3d& a, const Vec3d& b, const Vec3d& c, double inv[9]) {
  // Rows of the inverse are the cross products of the columns over the determinant.
  const Vec3d r0{b.y * c.z - b.z * c.y, b.z * c.x - b.x * c.z, b.x * c.y - b.y * c.x};
  const Vec3d r1{c.y * a.z - c.z * a.y, c.z * a.x - c.x * a.z, c.x * a.y - c.y * a.x};
  const Vec3d r2{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  const double det = dot(a, r0);
  if (!(std::abs(det) > 1e-300)) return false;
  const Vec3d rows[3] = {r0, r1, r2};
  for (int r = 0; r < 3; ++r) {
    inv[3 * r] = rows[r].x / det;
    inv[3 * r + 1] = rows[r].y / det;
    inv[3 * r + 2] = rows[r].z / det;
  }
  return true;
}

}  // namespace

double convexHullGauge(const Vec3d* w, std::size_t count, const Vec3d& v) {
  if (v.x == 0.0 && v.y == 0.0 && v.z == 0.0) return 0.0;
  // Columns 0..count-1 are the points (cost 1 each); count + k is the
  // artificial column sign(v_k) e_k with a cost that no combination of the
  // points approaches (big M), so the first basis is feasible: x = |v_k|.
  double scale = 0.0;
  for (std::size_t i = 0; i < count; ++i) scale = std::max(scale, std::sqrt(dot(w[i], w[i])));
  double shortest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < count; ++i) shortest = std::min(shortest, std::sqrt(dot(w[i], w[i])));
  if (!(shortest > 0.0)) throw std::invalid_argument("convex hull gauge: a point is at the origin");
  const double bigM = 1e6 / shortest;
  const Vec3d artificial[3] = {{v.x < 0 ? -1.0 : 1.0, 0, 0}, {0, v.y < 0 ? -1.0 : 1.0, 0}, {0, 0, v.z < 0 ? -1.0 : 1.0}};
  auto column = [&](std::size_t j) -> const Vec3d& { return j < count ? w[j] : artificial[j - count]; };
  auto costOf = [&](std::size_t j) { return j < count ? 1.0 : bigM; };

  std::size_t basis[3] = {count, count + 1, count + 2};
  double x[3] = {std::abs(v.x), std::abs(v.y), std::abs(v.z)};
  double inv[9];
  const double tolerance = 1e-12;
  for (int iteration = 0; iteration < 500; ++iteration) {
    if (!invertColumns(column(basis[0]), column(basis[1]), column(basis[2]), inv))
      throw std::invalid_argument("convex hull gauge: singular basis");
    // Prices: y = B^-T c_B.
    const double cb[3] = {costOf(basis[0]), costOf(basis[1]), costOf(basis[2])};
    const Vec3d y{inv[0] * cb[0] + inv[3] * cb[1] + inv[6] * cb[2], inv[1] * cb[0] + inv[4] * cb[1] + inv[7] * cb[2],
                  inv[2] * cb[0] + inv[5] * cb[1] + inv[8] * cb[2]};
    // Entering column: the most negative reduced cost (Dantzig), or the
    // first negative one (Bland, which cannot cycle) after many steps.
    const bool bland = iteration >= 100;
    std::size_t entering = count + 3;
    double best = -tolerance * (1.0 + scale * std::sqrt(dot(y, y)));
    for (std::size_t j = 0; j < count; ++j) {
      const double r = 1.0 - dot(y, w[j]);
      if (r < best) {
        best = r;
        entering = j;
        if (bland) break;
      }
    }
    if (entering == count + 3) {
      double value = 0.0;
      for (int k = 0; k < 3; ++k) {
        if (basis[k] >= count && x[k] > 1e-9 * (x[0] + x[1] + x[2]))
          throw std::invalid_argument("convex hull gauge: the points do not surround the direction");
        value += cb[k] * x[k];
      }
      return value;
    }
    const Vec3d& a = column(entering);
    const double d[3] = {inv[0] * a.x + inv[1] * a.y + inv[2] * a.z, inv[3] * a.x + inv[4] * a.y + inv[5] * a.z,
                         inv[6] * a.x + inv[7] * a.y + inv[8] * a.z};
    int leaving = -1;
    double ratio = std::numeric_limits<double>::infinity();
    // Leaving row: the smallest ratio; among ties an artificial column
    // first, and under Bland's rule the smallest column index (Bland's
    // leaving rule: without it a degenerate vertex, many points on one
    // facet, can cycle; a real FOD voxel did).
    for (int k = 0; k < 3; ++k)
      if (d[k] > 1e-14) {
        const double r = x[k] / d[k];
        const bool tie = r == ratio && leaving >= 0;
        if (r < ratio || (tie && (bland ? basis[k] < basis[leaving] : basis[k] >= count))) {
          ratio = r;
          leaving = k;
        }
      }
    if (leaving < 0) throw std::invalid_argument("convex hull gauge: unbounded (a point of negative cost?)");
    for (int k = 0; k < 3; ++k) x[k] = std::max(0.0, x[k] - ratio * d[k]);
    x[leaving] = ratio;
    basis[leaving] = entering;
  }
  throw std::invalid_argument("convex hull gauge: the simplex method did not converge");
}

void ConvexHullGauges::reset(const Vec3d* w, std::size_t count) {
  count_ = count;
  points_.assign(w, w + count);
  px_.resize(count);
  py_.resize(count);
  pz_.resize(count);
  active_.assign(count, 0);
  activeList_.clear();
  facets_.clear();
  double scale = 0.0, shortest = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < count; ++i) {
    px_[i] = w[i].x;
    py_[i] = w[i].y;
    pz_[i] = w[i].z;
    const double length = std::sqrt(dot(w[i], w[i]));
    scale = std::max(scale, length);
    shortest = std::min(shortest, length);
  }
  if (count > 0 && !(shortest > 0.0)) throw std::invalid_argument("convex hull gauge: a point is at the origin");
  scale_ = scale;
  bigM_ = 1e6 / shortest;
}

void ConvexHullGauges::activate(std::size_t j) {
  if (!active_[j]) {
    active_[j] = 1;
    activeList_.push_back(static_cast<int>(j));
  }
}

double ConvexHullGauges::operator()(const Vec3d& v) {
  if (v.x == 0.0 && v.y == 0.0 && v.z == 0.0) return 0.0;
  try {
    return solve(v);
  } catch (const std::invalid_argument&) {
    // Whatever the fast path stumbles on (a degenerate pivot), the plain
    // method over every point decides, or throws its own message.
    return convexHullGauge(points_.data(), points_.size(), v);
  }
}

double ConvexHullGauges::solve(const Vec3d& v) {
  if (count_ == 0) throw std::invalid_argument("convex hull gauge: the points do not surround the direction");
  // A facet found before whose cone holds v: its basis is feasible for v
  // and its prices are feasible for every point (that is how it was found),
  // so it is optimal for v too.
  for (const Facet& f : facets_) {
    const double x0 = f.inv[0] * v.x + f.inv[1] * v.y + f.inv[2] * v.z;
    const double x1 = f.inv[3] * v.x + f.inv[4] * v.y + f.inv[5] * v.z;
    const double x2 = f.inv[6] * v.x + f.inv[7] * v.y + f.inv[8] * v.z;
    const double slack = -1e-12 * (std::abs(x0) + std::abs(x1) + std::abs(x2));
    if (x0 >= slack && x1 >= slack && x2 >= slack) return x0 + x1 + x2;
  }
  // The simplex method of convexHullGauge (the same start, the same
  // optimality test against every point), pricing first the points that
  // entered a basis or priced best before ("active") and all of them only
  // when none of those improves: the prices of one voxel's directions pick
  // among few of its points.
  const std::size_t count = count_;
  const Vec3d artificial[3] = {{v.x < 0 ? -1.0 : 1.0, 0, 0}, {0, v.y < 0 ? -1.0 : 1.0, 0}, {0, 0, v.z < 0 ? -1.0 : 1.0}};
  auto column = [&](std::size_t j) -> Vec3d { return j < count ? Vec3d{px_[j], py_[j], pz_[j]} : artificial[j - count]; };
  auto costOf = [&](std::size_t j) { return j < count ? 1.0 : bigM_; };
  std::size_t basis[3] = {count, count + 1, count + 2};
  double x[3] = {std::abs(v.x), std::abs(v.y), std::abs(v.z)};
  double inv[9];
  for (int iteration = 0; iteration < 500; ++iteration) {
    if (!invertColumns(column(basis[0]), column(basis[1]), column(basis[2]), inv))
      throw std::invalid_argument("convex hull gauge: singular basis");
    const double cb[3] = {costOf(basis[0]), costOf(basis[1]), costOf(basis[2])};
    const Vec3d y{inv[0] * cb[0] + inv[3] * cb[1] + inv[6] * cb[2], inv[1] * cb[0] + inv[4] * cb[1] + inv[7] * cb[2],
                  inv[2] * cb[0] + inv[5] * cb[1] + inv[8] * cb[2]};
    const bool bland = iteration >= 100;
    const double threshold = -1e-12 * (1.0 + scale_ * std::sqrt(dot(y, y)));
    std::size_t entering = count + 3;
    double best = threshold;
    if (!bland)
      for (int j : activeList_) {
        const double r = 1.0 - (y.x * px_[static_cast<std::size_t>(j)] + y.y * py_[static_cast<std::size_t>(j)] +
                                y.z * pz_[static_cast<std::size_t>(j)]);
        if (r < best) {
          best = r;
          entering = static_cast<std::size_t>(j);
        }
      }
    if (entering == count + 3) {
      // Every point, by coordinate arrays; the few best join the active
      // points. Bland's rule (after many steps) takes the first in order.
      const double* px = px_.data();
      const double* py = py_.data();
      const double* pz = pz_.data();
      constexpr int kJoin = 4;
      std::size_t top[kJoin];
      double topCost[kJoin];
      int topCount = 0;
      if (bland) {
        for (std::size_t j = 0; j < count; ++j)
          if (1.0 - (y.x * px[j] + y.y * py[j] + y.z * pz[j]) < threshold) {
            entering = j;
            break;
          }
      } else {
        for (std::size_t j = 0; j < count; ++j) {
          const double r = 1.0 - (y.x * px[j] + y.y * py[j] + y.z * pz[j]);
          if (!(r < threshold)) continue;
          if (topCount == kJoin && !(r < topCost[kJoin - 1])) continue;
          int at = topCount < kJoin ? topCount++ : kJoin - 1;  // keep the kJoin most negative, in order
          while (at > 0 && r < topCost[at - 1]) {
            top[at] = top[at - 1];
            topCost[at] = topCost[at - 1];
            --at;
          }
          top[at] = j;
          topCost[at] = r;
        }
        if (topCount > 0) {
          entering = top[0];
          for (int t = 0; t < topCount; ++t) activate(top[t]);
        }
      }
    }
    if (entering == count + 3) {
      double value = 0.0;
      for (int k = 0; k < 3; ++k) {
        if (basis[k] >= count && x[k] > 1e-9 * (x[0] + x[1] + x[2]))
          throw std::invalid_argument("convex hull gauge: the points do not surround the direction");
        value += cb[k] * x[k];
      }
      if (basis[0] < count && basis[1] < count && basis[2] < count) {
        Facet f;
        std::copy(inv, inv + 9, f.inv);
        facets_.push_back(f);
      }
      return value;
    }
    const Vec3d a = column(entering);
    const double d[3] = {inv[0] * a.x + inv[1] * a.y + inv[2] * a.z, inv[3] * a.x + inv[4] * a.y + inv[5] * a.z,
                         inv[6] * a.x + inv[7] * a.y + inv[8] * a.z};
    // A pivot element must be more than rounding against the others: a
    // column in the plane of two basic ones (points on one great circle)
    // has a third component of rounding only, and pivoting on it would make
    // the basis singular.
    const double pivotTolerance = std::max(1e-14, 1e-11 * std::max({std::abs(d[0]), std::abs(d[1]), std::abs(d[2])}));
    int leaving = -1;
    double ratio = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 3; ++k)
      if (d[k] > pivotTolerance) {
        const double r = x[k] / d[k];
        if (r < ratio || (r == ratio && basis[k] >= count)) {
          ratio = r;
          leaving = k;
        }
      }
    if (leaving < 0) throw std::invalid_argument("convex hull gauge: unbounded (a point of negative cost?)");
    for (int k = 0; k < 3; ++k) x[k] = std::max(0.0, x[k] - ratio * d[k]);
    x[leaving] = ratio;
    basis[leaving] = entering;
    if (entering < count) activate(entering);
  }
  throw std::invalid_argument("convex hull gauge: the simplex method did not converge");
}

std::vector<float> convexifiedFodNormsReference(const FodCostSampler& sampler, const std::vector<Vec3d>& queries) {
  std::vector<std::size_t> opposite(queries.size(), queries.size());
  for (std::size_t q = 0; q < queries.size(); ++q)
    for (std::size_t p = 0; p < q && opposite[q] == queries.size(); ++p)
      if (queries[p].x == -queries[q].x && queries[p].y == -queries[q].y && queries[p].z == -queries[q].z)
        opposite[q] = p;
  const std::size_t voxels = sampler.voxelCount();
  std::vector<float> out(voxels * queries.size());
  FodUnitBall ball;
  for (std::size_t v = 0; v < voxels; ++v) {
    sampler.unitBallReference(v, ball);
    float* row = out.data() + v * queries.size();
    for (std::size_t q = 0; q < queries.size(); ++q)
      row[q] = opposite[q] < q ? row[opposite[q]]
                               : static_cast<float>(convexHullGauge(ball.points.data(), ball.points.size(), queries[q]));
  }
  return out;
}

}  // namespace stvd::imaging
