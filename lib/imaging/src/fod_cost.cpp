#include "stvd/imaging/fod_cost.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <utility>

#include "stvd/imaging/spherical_harmonics.hpp"

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
  std::vector<Vec3d> d = icosphereDirections(subdivisions);
  const std::vector<Vec3d> n = neighbourDirections26(geometry);
  d.insert(d.end(), n.begin(), n.end());
  return d;
}

FodCostSampler::FodCostSampler(const FodField& field, std::vector<Vec3d> directions, FodCostOptions options)
    : field_(field), directions_(std::move(directions)), options_(options) {
  options_.validate();
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
}

double FodCostSampler::amplitudeAt(const float* c, const Vec3d& unitLps) const {
  const Vec3d s = field_.toShFrame(unitLps);
  double y[91];
  evaluateShBasis(field_.basis, field_.lmax, s.x, s.y, s.z, y);
  double a = 0.0;
  for (int j = 0, n = field_.coefficientCount(); j < n; ++j) a += y[j] * c[j];
  return a;
}

Vec3d FodCostSampler::refinePeak(const float* c, Vec3d u, double* amplitude) const {
  // A pattern search on the sphere: steps along two tangent directions,
  // halved when none improves, from half a spacing down to 1e-3 rad (0.06
  // degrees; F* = F = 1 at the point found, however precise).
  double best = amplitudeAt(c, u);
  for (double step = 0.5 * spacing_; step > 1e-3;) {
    const Vec3d helper = std::abs(u.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
    const Vec3d t1 = normalised(helper - dot(helper, u) * u);
    const Vec3d t2{u.y * t1.z - u.z * t1.y, u.z * t1.x - u.x * t1.z, u.x * t1.y - u.y * t1.x};
    Vec3d next = u;
    double nextValue = best;
    for (const Vec3d& t : {t1, -1.0 * t1, t2, -1.0 * t2}) {
      const Vec3d candidate = normalised(u + step * t);
      const double value = amplitudeAt(c, candidate);
      if (value > nextValue) {
        nextValue = value;
        next = candidate;
      }
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

void FodCostSampler::unitBall(std::size_t v, FodUnitBall& ball) const {
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
  // The local maxima over the sampling directions, refined.
  std::vector<double> peakValues;
  for (std::size_t i = 0; i < n; ++i) {
    if (a[i] < options_.floor * amax) continue;
    bool isMax = true;
    for (int j : neighbours_[i]) isMax = isMax && a[i] >= a[j];
    if (!isMax) continue;
    double value = 0.0;
    ball.peaks.push_back(refinePeak(c, directions_[i], &value));
    peakValues.push_back(value);
    amax = std::max(amax, value);
  }
  ball.amplitudeMax = amax;
  for (std::size_t i = 0; i < n; ++i)
    ball.points[i] = std::pow(std::max(options_.floor, std::min(1.0, a[i] / amax)), options_.power) * directions_[i];
  for (std::size_t k = 0; k < ball.peaks.size(); ++k)
    ball.points.push_back(std::pow(std::max(options_.floor, std::min(1.0, peakValues[k] / amax)), options_.power) *
                          ball.peaks[k]);
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
        const bool preferred = bland ? basis[k] < basis[leaving] : basis[k] >= count;
        if (r < ratio || (tie && preferred)) {
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

std::vector<float> convexifiedFodNorms(const FodCostSampler& sampler, const std::vector<Vec3d>& queries) {
  // F* is symmetric (an FOD is): a query whose opposite came earlier takes
  // its value (the 26 neighbour directions are 13 pairs).
  std::vector<std::size_t> opposite(queries.size(), queries.size());
  for (std::size_t q = 0; q < queries.size(); ++q)
    for (std::size_t p = 0; p < q && opposite[q] == queries.size(); ++p)
      if (queries[p].x == -queries[q].x && queries[p].y == -queries[q].y && queries[p].z == -queries[q].z)
        opposite[q] = p;
  const std::size_t voxels = sampler.voxelCount();
  std::vector<float> out(voxels * queries.size());
  FodUnitBall ball;
  for (std::size_t v = 0; v < voxels; ++v) {
    sampler.unitBall(v, ball);
    float* row = out.data() + v * queries.size();
    for (std::size_t q = 0; q < queries.size(); ++q)
      row[q] = opposite[q] < q ? row[opposite[q]]
                               : static_cast<float>(convexHullGauge(ball.points.data(), ball.points.size(), queries[q]));
  }
  return out;
}

}  // namespace stvd::imaging
