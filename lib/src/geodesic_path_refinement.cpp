#include "stvd/geodesic_path_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "grid_cell_sample.hpp"

namespace stvd {
namespace {

using detail::CellSample;
using detail::locate;
using detail::Sym3;

/// A general 3x3 matrix, row-major: the blocks of the tridiagonal solve.
struct Block {
  double m[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
  static Block from(const Sym3& s) {
    Block b;
    b.m[0] = s.xx, b.m[1] = s.xy, b.m[2] = s.xz;
    b.m[3] = s.xy, b.m[4] = s.yy, b.m[5] = s.yz;
    b.m[6] = s.xz, b.m[7] = s.yz, b.m[8] = s.zz;
    return b;
  }
};

Block multiply(const Block& a, const Block& b) {
  Block c;
  for (int r = 0; r < 3; ++r)
    for (int k = 0; k < 3; ++k)
      c.m[3 * r + k] = a.m[3 * r] * b.m[k] + a.m[3 * r + 1] * b.m[3 + k] + a.m[3 * r + 2] * b.m[6 + k];
  return c;
}

Vec3d multiply(const Block& a, Vec3d v) {
  return {a.m[0] * v.x + a.m[1] * v.y + a.m[2] * v.z, a.m[3] * v.x + a.m[4] * v.y + a.m[5] * v.z,
          a.m[6] * v.x + a.m[7] * v.y + a.m[8] * v.z};
}

bool invert(const Block& a, Block& out) {
  const double* m = a.m;
  const double c00 = m[4] * m[8] - m[5] * m[7], c01 = m[5] * m[6] - m[3] * m[8], c02 = m[3] * m[7] - m[4] * m[6];
  const double det = m[0] * c00 + m[1] * c01 + m[2] * c02;
  if (!std::isfinite(det) || det == 0.0) return false;
  const double inv = 1.0 / det;
  out.m[0] = c00 * inv;
  out.m[1] = (m[2] * m[7] - m[1] * m[8]) * inv;
  out.m[2] = (m[1] * m[5] - m[2] * m[4]) * inv;
  out.m[3] = c01 * inv;
  out.m[4] = (m[0] * m[8] - m[2] * m[6]) * inv;
  out.m[5] = (m[2] * m[3] - m[0] * m[5]) * inv;
  out.m[6] = c02 * inv;
  out.m[7] = (m[1] * m[6] - m[0] * m[7]) * inv;
  out.m[8] = (m[0] * m[4] - m[1] * m[3]) * inv;
  return std::isfinite(out.m[0]) && std::isfinite(out.m[4]) && std::isfinite(out.m[8]);
}

double maxAbs(Vec3d v) { return std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)}); }

/// Segments may span at most this much along each index axis: then a
/// segment between two points whose cells lie in the domain cannot reach
/// the inside of a voxel outside it (entering that voxel's box from outside
/// the four cells around it takes more than half a voxel along two axes).
constexpr double kMaxSegmentVoxels = 0.5;

/// The refinement works in continuous index coordinates c (x = origin +
/// D S c), where the box constraint is a clamp and the domain test a cell
/// lookup; G is carried over as A^T G A with A = D S.
class PathRefiner {
 public:
  PathRefiner(const VoxelGridDomain& domain, const RiemannianMetric& metric, const std::vector<double>& distance,
              const PathRefinementOptions& options)
      : domain_(domain), geometry_(domain.geometry()), metric_(metric), distance_(distance), options_(options) {
    for (int c = 0; c < 3; ++c) {
      const Vec3d column = geometry_.indexToPhysicalOffset(c == 0, c == 1, c == 2);
      toPhysical_.m[c] = column.x, toPhysical_.m[3 + c] = column.y, toPhysical_.m[6 + c] = column.z;
    }
    for (int a = 0; a < 3; ++a) last_[a] = std::max(0.0, static_cast<double>(geometry_.size[a]) - 1.0);
  }

  PathRefinementReport refine(std::vector<Vec3d>& points) {
    PathRefinementReport report;
    if (points.size() < 2 || norm(points.back() - points.front()) == 0.0) return report;
    std::vector<Vec3d> input(points.size());
    for (std::size_t n = 0; n < points.size(); ++n) input[n] = clamp(geometry_.physicalPointToIndex(points[n]));
    if (!resample(input, x_)) return report;
    const std::size_t count = x_.size();
    y_.resize(count);
    gradient_.assign(count, Vec3d{});
    delta_.assign(count, Vec3d{});
    segmentMetric_.resize(count - 1);
    moved_.resize(count);
    valid_.resize(count);
    forward_.resize(count);
    rhs_.resize(count);

    double energy = 0.0;
    if (!evaluate(x_, true, energy)) return report;
    report.initialEnergy = report.finalEnergy = energy;
    for (int iteration = 0; iteration < options_.maxIterations; ++iteration) {
      if (!solve()) break;
      bool accepted = false;
      double alpha = 1.0, trial = 0.0;
      std::size_t held = 0;
      for (int halving = 0; halving <= options_.maxHalvings && !accepted; ++halving, alpha *= 0.5) {
        held = propose(alpha);
        accepted = evaluate(y_, false, trial) && trial < energy;
      }
      if (!accepted) {
        report.converged = true;
        break;
      }
      double largestMove = 0.0;
      for (std::size_t n = 0; n < count; ++n) largestMove = std::max(largestMove, maxAbs(y_[n] - x_[n]));
      x_.swap(y_);
      energy = trial;
      ++report.iterations;
      report.heldMoves += held;
      if (largestMove < options_.tolerance) {
        report.converged = true;
        break;
      }
      if (!evaluate(x_, true, energy)) break;
    }
    report.finalEnergy = energy;
    const Vec3d first = points.front(), lastPoint = points.back();
    points.resize(count);
    for (std::size_t n = 1; n + 1 < count; ++n) points[n] = geometry_.indexToPhysicalPoint(x_[n].x, x_[n].y, x_[n].z);
    // The end points keep their exact input coordinates.
    points.front() = first;
    points.back() = lastPoint;
    return report;
  }

 private:
  Vec3d clamp(Vec3d c) const {
    return {std::clamp(c.x, 0.0, last_[0]), std::clamp(c.y, 0.0, last_[1]), std::clamp(c.z, 0.0, last_[2])};
  }

  /// Every corner with a non-zero weight is in the domain and reached.
  bool valid(Vec3d c) const {
    CellSample cell;
    if (!locate(domain_, c, cell)) return false;
    for (int n = 0; n < 8; ++n)
      if (cell.weight[n] > 0.0 && (!domain_.contains(cell.corner[n]) || !std::isfinite(distance_[cell.corner[n]])))
        return false;
    return true;
  }

  /// q = e^T G(m) e for the index displacement e with G (physical)
  /// interpolated at the index point m over the valid corners; with
  /// `derivatives`, also G in index coordinates and dq/dm. False when no
  /// corner is valid.
  bool segment(Vec3d m, Vec3d e, bool derivatives, double& q, Sym3& gIndex, Vec3d& dqdm) const {
    CellSample cell;
    if (!locate(domain_, m, cell)) return false;
    const Vec3d d = multiply(toPhysical_, e);
    double qn[8];
    double total = 0.0;
    bool complete = true;
    Sym3 g;
    q = 0.0;
    for (int n = 0; n < 8; ++n) {
      qn[n] = 0.0;
      if (cell.weight[n] <= 0.0) continue;
      const VertexId v = cell.corner[n];
      if (!domain_.contains(v) || !std::isfinite(distance_[v])) {
        complete = false;
        continue;
      }
      const SymTensor3& t = metric_[v];
      Sym3 corner;
      corner.add(1.0, t);
      qn[n] = corner.quadraticForm(d);
      q += cell.weight[n] * qn[n];
      total += cell.weight[n];
      if (derivatives) g.add(cell.weight[n], t);
    }
    if (!(total > 0.0)) return false;
    q /= total;
    if (!derivatives) return true;
    const double scale = 1.0 / total;
    g.xx *= scale, g.xy *= scale, g.xz *= scale, g.yy *= scale, g.yz *= scale, g.zz *= scale;
    // A^T G A.
    const Block ga = multiply(Block::from(g), toPhysical_);
    Block at;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) at.m[3 * r + c] = toPhysical_.m[3 * c + r];
    const Block gi = multiply(at, ga);
    gIndex.xx = gi.m[0], gIndex.xy = gi.m[1], gIndex.xz = gi.m[2];
    gIndex.yy = gi.m[4], gIndex.yz = gi.m[5], gIndex.zz = gi.m[8];
    dqdm = {};
    // A cell with corners outside the domain (a point the constraint holds
    // in place) contributes no gradient of G: the renormalised weights are
    // not the trilinear ones there.
    if (!complete) return true;
    double grad[3] = {0, 0, 0};
    for (int n = 0; n < 8; ++n) {
      const double w[3] = {(n & 1) ? cell.frac[0] : 1.0 - cell.frac[0], (n & 2) ? cell.frac[1] : 1.0 - cell.frac[1],
                           (n & 4) ? cell.frac[2] : 1.0 - cell.frac[2]};
      const double sign[3] = {(n & 1) ? 1.0 : -1.0, (n & 2) ? 1.0 : -1.0, (n & 4) ? 1.0 : -1.0};
      grad[0] += sign[0] * w[1] * w[2] * qn[n];
      grad[1] += sign[1] * w[0] * w[2] * qn[n];
      grad[2] += sign[2] * w[0] * w[1] * qn[n];
    }
    // Along a singleton axis the two "corners" are the same voxel, so the
    // derivative is zero, as it should be.
    dqdm = {grad[0], grad[1], grad[2]};
    return true;
  }

  /// E at the points c; with `derivatives`, also grad E and the segment
  /// metrics of the preconditioner.
  bool evaluate(const std::vector<Vec3d>& c, bool derivatives, double& energy) {
    energy = 0.0;
    if (derivatives) std::fill(gradient_.begin(), gradient_.end(), Vec3d{});
    for (std::size_t n = 0; n + 1 < c.size(); ++n) {
      const Vec3d e = c[n + 1] - c[n];
      double q = 0.0;
      Sym3 g;
      Vec3d dqdm;
      if (!segment(0.5 * (c[n] + c[n + 1]), e, derivatives, q, g, dqdm)) return false;
      energy += q;
      if (!derivatives) continue;
      segmentMetric_[n] = g;
      Vec3d ge;
      const Block b = Block::from(g);
      ge = multiply(b, e);
      gradient_[n] = gradient_[n] + (-2.0) * ge + 0.5 * dqdm;
      gradient_[n + 1] = gradient_[n + 1] + 2.0 * ge + 0.5 * dqdm;
    }
    return std::isfinite(energy);
  }

  /// delta = -H^-1 grad E over the interior points (block Thomas algorithm).
  bool solve() {
    const std::size_t count = x_.size();
    std::fill(delta_.begin(), delta_.end(), Vec3d{});
    if (count < 3) return false;
    Block previousForward;  // M_{i-1}^-1 B_{i-1}, B = -2 G(m_{i-1})
    Vec3d previousRhs;
    for (std::size_t i = 1; i + 1 < count; ++i) {
      Block diagonal = Block::from(segmentMetric_[i - 1]);
      const Block right = Block::from(segmentMetric_[i]);
      for (int k = 0; k < 9; ++k) diagonal.m[k] = 2.0 * (diagonal.m[k] + right.m[k]);
      Vec3d r = -1.0 * gradient_[i];
      if (i > 1) {
        Block leftOff = Block::from(segmentMetric_[i - 1]);
        for (double& v : leftOff.m) v *= -2.0;
        const Block correction = multiply(leftOff, previousForward);
        for (int k = 0; k < 9; ++k) diagonal.m[k] -= correction.m[k];
        r = r - multiply(leftOff, previousRhs);
      }
      Block inverse;
      if (!invert(diagonal, inverse)) return false;
      Block rightOff = right;
      for (double& v : rightOff.m) v *= -2.0;
      forward_[i] = multiply(inverse, rightOff);
      rhs_[i] = multiply(inverse, r);
      previousForward = forward_[i];
      previousRhs = rhs_[i];
    }
    delta_[count - 2] = rhs_[count - 2];
    for (std::size_t i = count - 2; i-- > 1;) delta_[i] = rhs_[i] - multiply(forward_[i], delta_[i + 1]);
    return true;
  }

  /// y = x + alpha delta, clamped to the box, with the moves that break the
  /// domain constraint taken back. Returns the number taken back.
  std::size_t propose(double alpha) {
    const std::size_t count = x_.size();
    std::size_t held = 0;
    y_.front() = x_.front();
    y_.back() = x_.back();
    moved_.front() = moved_.back() = 0;
    valid_.front() = valid(x_.front());
    valid_.back() = valid(x_.back());
    for (std::size_t n = 1; n + 1 < count; ++n) {
      y_[n] = clamp(x_[n] + alpha * delta_[n]);
      moved_[n] = 1;
      valid_[n] = valid(y_[n]);
      if (!valid_[n]) {
        y_[n] = x_[n];
        moved_[n] = 0;
        valid_[n] = valid(x_[n]);
        ++held;
      }
    }
    // A held point can invalidate its neighbours' segments: repeat until
    // every changed segment is short and joins valid points.
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t n = 0; n + 1 < count; ++n) {
        if (!moved_[n] && !moved_[n + 1]) continue;
        if (valid_[n] && valid_[n + 1] && maxAbs(y_[n + 1] - y_[n]) <= kMaxSegmentVoxels) continue;
        for (std::size_t k : {n, n + 1})
          if (moved_[k]) {
            y_[k] = x_[k];
            moved_[k] = 0;
            valid_[k] = valid(x_[k]);
            ++held;
          }
        changed = true;
      }
    }
    return held;
  }

  /// The polyline `in` (index points) resampled to equal metric spacing,
  /// with segments of at most spacingFraction voxel along every axis.
  bool resample(const std::vector<Vec3d>& in, std::vector<Vec3d>& out) const {
    std::vector<double> cumulative(in.size(), 0.0);
    double axisSum = 0.0;
    for (std::size_t n = 1; n < in.size(); ++n) {
      double q = 0.0;
      Sym3 g;
      Vec3d unused;
      if (!segment(0.5 * (in[n - 1] + in[n]), in[n] - in[n - 1], false, q, g, unused)) return false;
      cumulative[n] = cumulative[n - 1] + std::sqrt(std::max(0.0, q));
      axisSum += maxAbs(in[n] - in[n - 1]);
    }
    const double total = cumulative.back();
    if (!(total > 0.0)) return false;
    constexpr std::size_t kMaxSegments = 1u << 20;
    std::size_t segments = std::max<std::size_t>(1, static_cast<std::size_t>(std::ceil(axisSum / options_.spacingFraction)));
    for (int attempt = 0; attempt < 4; ++attempt) {
      segments = std::min(segments, kMaxSegments);
      out.assign(segments + 1, Vec3d{});
      out.front() = in.front();
      out.back() = in.back();
      std::size_t at = 1;
      for (std::size_t k = 1; k < segments; ++k) {
        const double s = total * static_cast<double>(k) / static_cast<double>(segments);
        while (at + 1 < in.size() && cumulative[at] < s) ++at;
        const double span = cumulative[at] - cumulative[at - 1];
        const double t = span > 0.0 ? std::clamp((s - cumulative[at - 1]) / span, 0.0, 1.0) : 0.0;
        out[k] = in[at - 1] + t * (in[at] - in[at - 1]);
      }
      double longest = 0.0;
      for (std::size_t k = 1; k < out.size(); ++k) longest = std::max(longest, maxAbs(out[k] - out[k - 1]));
      if (longest <= options_.spacingFraction || segments == kMaxSegments) return true;
      segments = static_cast<std::size_t>(std::ceil(1.05 * segments * longest / options_.spacingFraction));
    }
    return true;
  }

  const VoxelGridDomain& domain_;
  const GridGeometry& geometry_;
  const RiemannianMetric& metric_;
  const std::vector<double>& distance_;
  PathRefinementOptions options_;
  Block toPhysical_;
  double last_[3] = {0, 0, 0};
  // Work arrays, sized once per path.
  std::vector<Vec3d> x_, y_, gradient_, delta_, rhs_;
  std::vector<Sym3> segmentMetric_;
  std::vector<Block> forward_;
  std::vector<char> moved_, valid_;
};

}  // namespace

PathRefinementReport refineGeodesicPath(const VoxelGridDomain& domain, const RiemannianMetric& metric,
                                        const std::vector<double>& distance, std::vector<Vec3d>& points,
                                        const PathRefinementOptions& options) {
  if (metric.size() != domain.vertexCount() || distance.size() != domain.vertexCount())
    throw std::invalid_argument("metric, distance and domain differ in size");
  if (!(options.spacingFraction > 0.0 && options.spacingFraction <= kMaxSegmentVoxels) ||
      options.maxIterations < 0 || options.maxHalvings < 0 || !(options.tolerance > 0.0))
    throw std::invalid_argument("path refinement options out of range");
  return PathRefiner(domain, metric, distance, options).refine(points);
}

}  // namespace stvd
