#include "stvd/voxel_grid/path_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>

#include "grid_cell_sample.hpp"
#include "path_progress.hpp"

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

/// Coordinates within this distance (voxels) of the box of voxel centres
/// count as on it: points on an image face come out of the physical-to-
/// index conversion a rounding error inside or outside.
constexpr double kOnBoxVoxels = 1e-6;

/// Bisection steps when a point slides up to cells outside the domain
/// (2^-10 of its step).
constexpr int kSlideBisections = 10;

/// Rounds of fixing held points and solving again within one step.
constexpr int kMaxFixingRounds = 64;

/// The refinement works in continuous index coordinates c (x = origin +
/// D S c), where the box constraint is a clamp and the domain test a cell
/// lookup; G is carried over as A^T G A with A = D S.
class PathRefiner {
 public:
  /// Reports to `progress` from `from` to `from + span` of its total as the
  /// iterations go.
  PathRefiner(const VoxelGridDomain& domain, const RiemannianMetric& metric, const std::vector<double>& distance,
              const PathRefinementOptions& options, InterruptScope& progress, std::uint64_t from,
              std::uint64_t span)
      : domain_(domain),
        geometry_(domain.geometry()),
        metric_(metric),
        reached_{domain, distance},
        options_(options),
        progress_(progress),
        progressFrom_(from),
        progressSpan_(span) {
    for (int c = 0; c < 3; ++c) {
      const Vec3d column = geometry_.indexToPhysicalOffset(c == 0, c == 1, c == 2);
      toPhysical_.m[c] = column.x, toPhysical_.m[3 + c] = column.y, toPhysical_.m[6 + c] = column.z;
    }
    transposed_ = transpose(toPhysical_);
    for (int a = 0; a < 3; ++a) last_[a] = std::max(0.0, static_cast<double>(geometry_.size[a]) - 1.0);
  }

  PathRefinementReport refine(std::vector<Vec3d>& points) {
    PathRefinementReport report;
    if (points.size() < 2 || norm(points.back() - points.front()) == 0.0) return report;
    std::vector<Vec3d> input(points.size());
    for (std::size_t n = 0; n < points.size(); ++n) input[n] = clamp(geometry_.physicalPointToIndex(points[n]));
    std::vector<std::size_t> segmentOf;
    if (!resample(input, x_, segmentOf)) return report;
    restoreCorners(input, segmentOf, x_);
    const std::size_t count = x_.size();
    y_.resize(count);
    gradient_.assign(count, Vec3d{});
    delta_.assign(count, Vec3d{});
    blocks_.resize(count - 1);
    moved_.resize(count);
    forward_.resize(count);
    rhs_.resize(count);
    mask_.resize(count);

    double energy = 0.0;
    if (!evaluate(x_, true, energy)) return report;
    report.initialEnergy = report.finalEnergy = energy;
    // The line search starts at twice the last accepted step (at most the
    // full step): on a noisy metric the full Gauss-Newton step is often too
    // long, and halving down from it anew in every iteration cost about 5
    // energy evaluations per iteration on the sample brain.
    double startStep = 1.0;
    bool fixedAny = false;
    for (int iteration = 0; iteration < options_.maxIterations; ++iteration) {
      // An iteration and a halving cost O(N) each: the clock is read every
      // time (`points` is written only after the loop, so a stop leaves
      // them as they were).
      const std::uint64_t done =
          progressFrom_ + progressSpan_ * static_cast<std::uint64_t>(iteration) /
                              static_cast<std::uint64_t>(options_.maxIterations);
      progress_.check(done);
      setActiveBounds();
      if (!solve()) break;
      bool accepted = false, descends = true;
      double alpha = startStep, trial = 0.0;
      std::size_t held = 0;
      for (int halving = 0; halving <= options_.maxHalvings && descends && !accepted; ++halving, alpha *= 0.5) {
        if (halving > 0) progress_.check(done);
        if (halving > 0 && fixedAny) {
          // Points fixed for a longer step may be free to move on a
          // shorter one.
          setActiveBounds();
          if (!solve()) break;
        }
        fixedAny = false;
        held = propose(alpha);
        // Dropping the held points' moves from the step need not leave a
        // descent direction: fix them and solve again for the others.
        for (int round = 0; held > 0 && round < kMaxFixingRounds && fixHeldPoints(); ++round) {
          fixedAny = true;
          if (!solve()) {
            descends = false;
            break;
          }
          held = propose(alpha);
        }
        accepted = descends && evaluate(y_, false, trial) && trial < energy;
      }
      if (!accepted && startStep < 1.0) {
        // Nothing from the shortened start: the full range once more.
        startStep = 1.0;
        --iteration;
        continue;
      }
      if (!accepted) {
        report.converged = true;
        break;
      }
      double largestMove = 0.0;
      for (std::size_t n = 0; n < count; ++n) largestMove = std::max(largestMove, maxAbs(y_[n] - x_[n]));
      startStep = std::min(1.0, 4.0 * alpha);  // alpha was halved once more after the accepted trial
      x_.swap(y_);
      const double decrease = energy - trial;
      energy = trial;
      ++report.iterations;
      report.heldMoves += held;
      if (largestMove < options_.tolerance || decrease <= options_.energyTolerance * energy) {
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

  /// Every corner with a non-zero weight is in the domain and reached: where
  /// a point may move to (detail::kNewPointOnPlane).
  bool valid(Vec3d c) const { return detail::pointInRegion(domain_, c, reached_, detail::kNewPointOnPlane); }

  /// Every point of the segment a -> b is valid, or lies on a contact that
  /// the domain's connectivity joins (detail::segmentInRegion: exact, piece
  /// by piece between the crossings of integer planes).
  bool segmentValid(Vec3d a, Vec3d b) const { return detail::segmentInRegion(domain_, a, b, reached_); }

  /// The preconditioner's blocks of one segment, for its end points c_n,
  /// c_{n+1} (index coordinates): start (c_n, c_n), end (c_{n+1}, c_{n+1}),
  /// cross (c_n, c_{n+1}); cross^T is (c_{n+1}, c_n). Gauss-Newton's:
  /// 2 G, 2 G, -2 G (G = A^T G A in index coordinates), the Hessian of q
  /// without the derivatives of G. (Newton's blocks with the derivatives
  /// of the trilinear G took fewer iterations on the pull-back test scene,
  /// 13.8 against 16.4 on average, but ended farther from the exact
  /// geodesics, max 0.92 against 0.42 voxel, at no gain in time.)
  struct SegmentHessian {
    Block start, end, cross;
  };

  /// q = e^T G(m) e for the index displacement e with G (physical)
  /// interpolated at the index point m over the valid corners; with
  /// `derivatives`, also dq/dm and the segment's preconditioner blocks.
  /// False when no corner is valid.
  bool segment(Vec3d m, Vec3d e, bool derivatives, double& q, Vec3d& dqdm, SegmentHessian& blocks) const {
    CellSample cell;
    if (!locate(domain_, m, cell)) return false;
    const Vec3d d = multiply(toPhysical_, e);
    double qn[8];
    double total = 0.0;
    bool complete = true;
    Sym3 g;
    q = 0.0;
    // Corners of weight zero (a point on a cell face) still enter the
    // derivatives of the weights.
    for (int n = 0; n < 8; ++n) {
      qn[n] = 0.0;
      const VertexId v = cell.corner[n];
      if (!reached_(v)) {
        complete = false;
        continue;
      }
      const SymTensor3& t = metric_[v];
      Sym3 corner;
      corner.add(1.0, t);
      qn[n] = corner.quadraticForm(d);
      if (cell.weight[n] <= 0.0) continue;
      q += cell.weight[n] * qn[n];
      total += cell.weight[n];
      if (derivatives) g.add(cell.weight[n], t);
    }
    if (!(total > 0.0)) return false;
    q /= total;
    if (!derivatives) return true;
    const double scale = 1.0 / total;
    g.xx *= scale, g.xy *= scale, g.xz *= scale, g.yy *= scale, g.yz *= scale, g.zz *= scale;
    // q_ee = 2 A^T G A.
    Block qee = multiply(transposed_, multiply(Block::from(g), toPhysical_));
    for (double& v : qee.m) v *= 2.0;
    Block minusQee = qee;
    for (double& v : minusQee.m) v = -v;
    blocks = {qee, qee, minusQee};
    dqdm = {};
    // A cell with corners outside the domain contributes no derivative of
    // G (at a point held by the constraint the renormalised weights are not
    // the trilinear ones; on a face next to masked voxels only one side of
    // the derivative exists).
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

  /// E at the points c; with `derivatives`, also grad E and the segments'
  /// Hessian blocks.
  bool evaluate(const std::vector<Vec3d>& c, bool derivatives, double& energy) {
    energy = 0.0;
    if (derivatives) std::fill(gradient_.begin(), gradient_.end(), Vec3d{});
    for (std::size_t n = 0; n + 1 < c.size(); ++n) {
      const Vec3d e = c[n + 1] - c[n];
      double q = 0.0;
      Vec3d dqdm;
      if (!segment(0.5 * (c[n] + c[n + 1]), e, derivatives, q, dqdm, blocks_[n])) return false;
      energy += q;
      if (!derivatives) continue;
      // dq/de = 2 A^T G A e; blocks_[n].end = 2 A^T G A.
      const Vec3d ge = 0.5 * multiply(blocks_[n].end, e);
      gradient_[n] = gradient_[n] + (-2.0) * ge + 0.5 * dqdm;
      gradient_[n + 1] = gradient_[n + 1] + 2.0 * ge + 0.5 * dqdm;
    }
    return std::isfinite(energy);
  }

  /// Coordinates of point n that sit on the box and whose descent points
  /// out of it: bit a for axis a. They stay fixed in the step (a projected
  /// Newton step: clamping a preconditioned step afterwards need not
  /// descend, fixing these coordinates first does).
  int activeBounds(std::size_t n) const {
    const double c[3] = {x_[n].x, x_[n].y, x_[n].z};
    const double g[3] = {gradient_[n].x, gradient_[n].y, gradient_[n].z};
    int mask = 0;
    for (int a = 0; a < 3; ++a)
      if ((c[a] <= kOnBoxVoxels && g[a] > 0.0) || (c[a] >= last_[a] - kOnBoxVoxels && g[a] < 0.0) ||
          last_[a] == 0.0)
        mask |= 1 << a;
    return mask;
  }

  /// b with the rows of the fixed coordinates of the row point and the
  /// columns of those of the column point zeroed.
  static Block masked(const Block& b, int rowMask, int columnMask) {
    Block out = b;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        if (((rowMask >> r) & 1) || ((columnMask >> c) & 1)) out.m[3 * r + c] = 0.0;
    return out;
  }

  static Block transpose(const Block& b) {
    Block t;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) t.m[3 * r + c] = b.m[3 * c + r];
    return t;
  }

  /// delta = -H^-1 grad E over the interior points (block Thomas
  /// algorithm); false when a pivot is singular or delta is not a descent
  /// direction (rounding).
  bool solve() {
    const std::size_t count = x_.size();
    std::fill(delta_.begin(), delta_.end(), Vec3d{});
    if (count < 3) return false;
    const std::vector<SegmentHessian>& h = blocks_;
    Block previousForward;  // M_{i-1}^-1 H_{i-1,i}
    Vec3d previousRhs;
    for (std::size_t i = 1; i + 1 < count; ++i) {
      const int mask = mask_[i];
      Block diagonal;
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          const int k = 3 * r + c;
          diagonal.m[k] = ((mask >> r) & 1) || ((mask >> c) & 1) ? (r == c ? 1.0 : 0.0)
                                                                  : h[i - 1].end.m[k] + h[i].start.m[k];
        }
      Vec3d r = -1.0 * gradient_[i];
      if (mask & 1) r.x = 0.0;
      if (mask & 2) r.y = 0.0;
      if (mask & 4) r.z = 0.0;
      if (i > 1) {
        const Block lower = masked(transpose(h[i - 1].cross), mask, mask_[i - 1]);
        const Block correction = multiply(lower, previousForward);
        for (int k = 0; k < 9; ++k) diagonal.m[k] -= correction.m[k];
        r = r - multiply(lower, previousRhs);
      }
      Block inverse;
      if (!invert(diagonal, inverse)) return false;
      forward_[i] = multiply(inverse, masked(h[i].cross, mask, mask_[i + 1]));
      rhs_[i] = multiply(inverse, r);
      previousForward = forward_[i];
      previousRhs = rhs_[i];
    }
    delta_[count - 2] = rhs_[count - 2];
    for (std::size_t i = count - 2; i-- > 1;) delta_[i] = rhs_[i] - multiply(forward_[i], delta_[i + 1]);
    double slope = 0.0;
    for (std::size_t i = 1; i + 1 < count; ++i) slope += dot(gradient_[i], delta_[i]);
    return slope < 0.0 && std::isfinite(slope);
  }

  void setActiveBounds() {
    for (std::size_t n = 1; n + 1 < x_.size(); ++n) mask_[n] = activeBounds(n);
    mask_.front() = mask_.back() = 7;
  }

  /// Fixes every point whose move the last proposal took back; false when
  /// there was none left to fix.
  bool fixHeldPoints() {
    bool fixed = false;
    for (std::size_t n = 1; n + 1 < x_.size(); ++n)
      if (!moved_[n] && mask_[n] != 7) {
        mask_[n] = 7;
        fixed = true;
      }
    return fixed;
  }

  /// Moves `to` to the valid point reached from the valid point `from` by
  /// moving one axis at a time towards `to`, each as far as it stays valid
  /// (bisection): the region to avoid is a union of open axis-aligned cells,
  /// so this slides a point along its faces instead of stopping it short.
  /// False when the point would not move.
  bool slideTowards(Vec3d from, Vec3d& to) const {
    Vec3d at = from;
    const double target[3] = {to.x, to.y, to.z};
    bool movedAny = false;
    for (int a = 0; a < 3; ++a) {
      auto with = [&](double t) {
        Vec3d p = at;
        double& c = a == 0 ? p.x : a == 1 ? p.y : p.z;
        const double start = a == 0 ? at.x : a == 1 ? at.y : at.z;
        c = start + t * (target[a] - start);
        return p;
      };
      if ((a == 0 ? at.x : a == 1 ? at.y : at.z) == target[a]) continue;
      if (valid(with(1.0))) {
        at = with(1.0);
        movedAny = true;
        continue;
      }
      double good = 0.0, bad = 1.0;
      for (int b = 0; b < kSlideBisections; ++b) {
        const double mid = 0.5 * (good + bad);
        (valid(with(mid)) ? good : bad) = mid;
      }
      if (good > 0.0) {
        at = with(good);
        movedAny = true;
      }
    }
    to = at;
    return movedAny;
  }

  /// y = x + alpha delta, clamped to the box, with the moves that break the
  /// domain constraint taken back. Returns the number taken back.
  std::size_t propose(double alpha) {
    const std::size_t count = x_.size();
    std::size_t held = 0;
    y_.front() = x_.front();
    y_.back() = x_.back();
    moved_.front() = moved_.back() = 0;
    // A point moves only to a valid position (never onto a contact, which
    // it could not leave sideways).
    for (std::size_t n = 1; n + 1 < count; ++n) {
      if (mask_[n] == 7) {  // fixed for this step
        y_[n] = x_[n];
        moved_[n] = 0;
        continue;
      }
      y_[n] = clamp(x_[n] + alpha * delta_[n]);
      moved_[n] = 1;
      if (!valid(y_[n])) {
        ++held;
        if (!(valid(x_[n]) && slideTowards(x_[n], y_[n]))) {
          y_[n] = x_[n];
          moved_[n] = 0;
        }
      }
    }
    // A held point can invalidate its neighbours' segments: repeat until
    // every changed segment keeps to the region.
    for (bool changed = true; changed;) {
      changed = false;
      for (std::size_t n = 0; n + 1 < count; ++n) {
        if (!moved_[n] && !moved_[n + 1]) continue;
        if (segmentValid(y_[n], y_[n + 1])) continue;
        for (std::size_t k : {n, n + 1})
          if (moved_[k]) {
            y_[k] = x_[k];
            moved_[k] = 0;
            ++held;
          }
        changed = true;
      }
    }
    return held;
  }

  /// The polyline `in` (index points) resampled to equal metric spacing,
  /// with segments of at most spacingFraction voxel along every axis;
  /// segmentOf[k]: the segment of `in` that out[k] lies on.
  bool resample(const std::vector<Vec3d>& in, std::vector<Vec3d>& out, std::vector<std::size_t>& segmentOf) const {
    std::vector<double> cumulative(in.size(), 0.0);
    double axisSum = 0.0;
    for (std::size_t n = 1; n < in.size(); ++n) {
      double q = 0.0;
      Vec3d unused;
      SegmentHessian unusedBlocks;
      if (!segment(0.5 * (in[n - 1] + in[n]), in[n] - in[n - 1], false, q, unused, unusedBlocks)) return false;
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
      segmentOf.assign(segments + 1, 0);
      out.front() = in.front();
      out.back() = in.back();
      segmentOf.back() = in.size() - 2;
      std::size_t at = 1;
      for (std::size_t k = 1; k < segments; ++k) {
        const double s = total * static_cast<double>(k) / static_cast<double>(segments);
        while (at + 1 < in.size() && cumulative[at] < s) ++at;
        const double span = cumulative[at] - cumulative[at - 1];
        const double t = span > 0.0 ? std::clamp((s - cumulative[at - 1]) / span, 0.0, 1.0) : 0.0;
        out[k] = in[at - 1] + t * (in[at] - in[at - 1]);
        segmentOf[k] = at - 1;
      }
      double longest = 0.0;
      for (std::size_t k = 1; k < out.size(); ++k) longest = std::max(longest, maxAbs(out[k] - out[k - 1]));
      if (longest <= options_.spacingFraction || segments == kMaxSegments) return true;
      segments = static_cast<std::size_t>(std::ceil(1.05 * segments * longest / options_.spacingFraction));
    }
    return true;
  }

  /// Where a chord of the resampled polyline `out` cuts a corner of `in`
  /// and leaves the region (around the end of a wall, at the ends of a
  /// contact), puts the corners of `in` between the chord's ends back, so
  /// that the refinement starts from a polyline inside the region when `in`
  /// is one.
  void restoreCorners(const std::vector<Vec3d>& in, const std::vector<std::size_t>& segmentOf,
                      std::vector<Vec3d>& out) const {
    std::vector<Vec3d> kept;
    kept.reserve(out.size());
    for (std::size_t k = 0; k + 1 < out.size(); ++k) {
      kept.push_back(out[k]);
      if (segmentOf[k] == segmentOf[k + 1] || segmentValid(out[k], out[k + 1])) continue;
      for (std::size_t v = segmentOf[k] + 1; v <= segmentOf[k + 1]; ++v)
        if (norm(in[v] - kept.back()) > 0.0 && norm(in[v] - out[k + 1]) > 0.0) kept.push_back(in[v]);
    }
    kept.push_back(out.back());
    out.swap(kept);
  }

  const VoxelGridDomain& domain_;
  const GridGeometry& geometry_;
  const RiemannianMetric& metric_;
  detail::ReachedVoxel reached_;  // the voxels of the domain the propagation reached
  PathRefinementOptions options_;
  InterruptScope& progress_;
  std::uint64_t progressFrom_, progressSpan_;
  Block toPhysical_, transposed_;
  double last_[3] = {0, 0, 0};
  // Work arrays, sized once per path.
  std::vector<Vec3d> x_, y_, gradient_, delta_, rhs_;
  std::vector<SegmentHessian> blocks_;
  std::vector<Block> forward_;
  std::vector<char> moved_;
  std::vector<int> mask_;
};

}  // namespace

PathRefinementReport refineGeodesicPath(const VoxelGridDomain& domain, const RiemannianMetric& metric,
                                        const std::vector<double>& distance, std::vector<Vec3d>& points,
                                        const PathRefinementOptions& options) {
  if (metric.size() != domain.vertexCount() || distance.size() != domain.vertexCount())
    throw std::invalid_argument("metric, distance and domain differ in size");
  if (!(options.spacingFraction > 0.0 && options.spacingFraction <= 0.5) ||
      options.maxIterations < 0 || options.maxHalvings < 0 || !(options.tolerance > 0.0))
    throw std::invalid_argument("path refinement options out of range");
  InterruptScope progress(options.interrupter, "path refinement", kPathRefinementSteps, options.progressInterval);
  const PathRefinementReport report =
      PathRefiner(domain, metric, distance, options, progress, 0, kPathRefinementSteps).refine(points);
  progress.finish();
  return report;
}

namespace detail {

PathRefinementReport refineGeodesicPath(const VoxelGridDomain& domain, const RiemannianMetric& metric,
                                        const std::vector<double>& distance, std::vector<Vec3d>& points,
                                        const PathRefinementOptions& options, InterruptScope& progress,
                                        std::uint64_t from, std::uint64_t span) {
  return PathRefiner(domain, metric, distance, options, progress, from, span).refine(points);
}

}  // namespace detail

}  // namespace stvd
