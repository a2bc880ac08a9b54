#include "stvd/voxel_grid/path_tracing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include "grid_cell_sample.hpp"
#include "path_progress.hpp"

namespace stvd {
namespace {

using detail::CellSample;
using detail::locate;
using detail::Sym3;

/// The cell of c clamped into the box of voxel centres (always found): for
/// positions the tracer has already accepted.
CellSample locateClamped(const VoxelGridDomain& domain, Vec3d c) {
  const auto& size = domain.geometry().size;
  const double last[3] = {size[0] - 1.0, size[1] - 1.0, size[2] - 1.0};
  const Vec3d clamped{std::clamp(c.x, 0.0, last[0]), std::clamp(c.y, 0.0, last[1]), std::clamp(c.z, 0.0, last[2])};
  CellSample s;
  locate(domain, clamped, s);
  return s;
}

/// x moved into the box of voxel centres (its continuous index clamped):
/// the descent slides along the image border instead of leaving it.
Vec3d clampToImage(const GridGeometry& g, Vec3d x) {
  const Vec3d c = g.physicalPointToIndex(x);
  const double ci[3] = {c.x, c.y, c.z};
  double clamped[3];
  bool moved = false;
  for (int a = 0; a < 3; ++a) {
    const double last = g.size[a] == 1 ? 0.0 : static_cast<double>(g.size[a]) - 1.0;
    clamped[a] = std::clamp(ci[a], 0.0, last);
    moved = moved || clamped[a] != ci[a];
  }
  return moved ? g.indexToPhysicalPoint(clamped[0], clamped[1], clamped[2]) : x;
}

class PathTracer {
 public:
  /// The descent reports the first half of `progress`'s kTracingSteps, the
  /// refinement the second.
  static constexpr std::uint64_t kHalf = kPathRefinementSteps;
  static constexpr std::uint64_t kTracingSteps = 2 * kHalf;

  PathTracer(const VoxelGridDomain& domain, const RiemannianMetric& metric,
             const PropagationResult& result, const PathTracingOptions& options, InterruptScope& progress)
      : domain_(domain), geometry_(domain.geometry()), metric_(metric), u_(result.distance),
        reached_{domain, result.distance}, result_(result), options_(options), progress_(progress) {
    const auto& s = geometry_.spacing;
    step_ = options.stepFraction * std::min({s[0], s[1], s[2]});
  }

  TracedPath trace(VertexId target) {
    TracedPath path;
    path.discrete = predecessorPath(result_, target);
    if (path.discrete.empty()) return path;
    path.geodesicLength = u_[target];
    double discreteLength = 0.0;
    for (std::size_t n = 1; n < path.discrete.size(); ++n)
      discreteLength += norm(domain_.physicalPoint(path.discrete[n]) - domain_.physicalPoint(path.discrete[n - 1]));
    const double budget = std::ceil(options_.stepBudgetFactor * discreteLength / step_) + 16.0;
    std::size_t stepsLeft = static_cast<std::size_t>(budget);

    // Traced from the target down to a source; reversed at the end.
    std::vector<Vec3d>& points = path.points;
    Vec3d x = domain_.physicalPoint(target);
    points.push_back(x);
    bool gradientAllowed = true;
    int noDescent = 0;
    double ux = u_[target];
    // Every pass either takes a Heun step (bounded by the budget) or moves
    // down the predecessor chain (bounded by the vertex count).
    const std::size_t safety = static_cast<std::size_t>(budget) + 2 * domain_.vertexCount() + 16;
    // The share of the descent done: how far the distance has come down
    // from the target's (never back).
    const double u0 = ux;
    std::uint64_t descended = 0;
    std::uint64_t moves = 0;  // Heun steps and chain vertices: the clock is read every 64
    auto moved = [&](double u) {
      if ((++moves & 63) != 0) return;
      const double share = u0 > 0.0 ? std::clamp(1.0 - u / u0, 0.0, 1.0) : 0.0;
      descended = std::max(descended, static_cast<std::uint64_t>(share * static_cast<double>(kHalf)));
      progress_.check(descended);
    };
    for (std::size_t pass = 0; pass < safety; ++pass) {
      moved(ux);
      const CellSample here = locateClamped(domain_, geometry_.physicalPointToIndex(x));
      if (const VertexId source = nearbySource(here, x); source != kNoVertex) {
        if (norm(domain_.physicalPoint(source) - x) > 0.0) points.push_back(domain_.physicalPoint(source));
        return finish(path);
      }
      PathFallback why = PathFallback::StepLimit;
      bool stepped = false;
      if (gradientAllowed && stepsLeft > 0) {
        Vec3d next;
        double unext = 0.0;
        if (heunStep(x, next, unext, why)) {
          --stepsLeft;
          ++path.gradientSteps;
          noDescent = unext < ux ? 0 : noDescent + 1;
          x = next;
          ux = unext;
          points.push_back(x);
          stepped = noDescent < options_.noDescentSteps;
          if (!stepped) why = PathFallback::NoDescent;
          if (stepped) continue;
        }
      }
      if (gradientAllowed && stepsLeft == 0) {
        why = PathFallback::StepLimit;
        gradientAllowed = false;
      }
      ++path.fallbacks[static_cast<int>(why)];
      // Jump to the lowest corner of the smallest cell face that holds x
      // (all of them reached, since x was), so that the jump stays in that
      // face, then follow the predecessor chain.
      const CellSample cell = locateClamped(domain_, geometry_.physicalPointToIndex(x));
      int moving;
      const int face = detail::faceCorners(cell, moving);
      VertexId v = kNoVertex;
      for (int n = 0; n < 8; ++n) {
        const VertexId c = cell.corner[n];
        if (((face >> n) & 1) && reached_(c) && (v == kNoVertex || u_[c] < u_[v])) v = c;
      }
      if (v == kNoVertex) throw std::logic_error("path tracing lost the domain");
      points.push_back(domain_.physicalPoint(v));
      ++path.discretePoints;
      const int chain = gradientAllowed ? options_.fallbackVertices : std::numeric_limits<int>::max();
      for (int n = 0; n < chain && result_.predecessor[v] != kNoVertex; ++n) {
        v = result_.predecessor[v];
        moved(u_[v]);
        points.push_back(domain_.physicalPoint(v));
        ++path.discretePoints;
      }
      if (result_.predecessor[v] == kNoVertex) return finish(path);  // at a source
      x = domain_.physicalPoint(v);
      ux = u_[v];
      noDescent = 0;
    }
    throw std::logic_error("path tracing from vertex " + std::to_string(target) + " did not terminate (" + std::to_string(path.gradientSteps) + " steps, " + std::to_string(path.fallbackCount()) + " fallbacks)");
  }

 private:
  /// A source corner of the cell within one step of x and joined to it
  /// inside the region, or kNoVertex.
  VertexId nearbySource(const CellSample& cell, Vec3d x) const {
    VertexId best = kNoVertex;
    double bestDistance = step_;
    for (int n = 0; n < 8; ++n) {
      const VertexId c = cell.corner[n];
      if (!domain_.contains(c) || u_[c] != 0.0) continue;
      const double d = norm(domain_.physicalPoint(c) - x);
      if (d <= bestDistance && inRegion(x, domain_.physicalPoint(c))) {
        bestDistance = d;
        best = c;
      }
    }
    return best;
  }

  /// f = u^2 at voxel (i, j, k) when it is in the image and the domain
  /// and reached.
  bool fieldAt(int i, int j, int k, double& f) const {
    if (!domain_.isInsideImage(i, j, k)) return false;
    const VertexId w = domain_.vertexAtUnchecked(i, j, k);
    if (!domain_.contains(w) || !std::isfinite(u_[w])) return false;
    f = u_[w] * u_[w];
    return true;
  }

  /// grad f at a voxel in index coordinates, f = u^2: central differences,
  /// second-order one-sided ones where a neighbour is outside the image, the
  /// domain or not reached (first-order when only one neighbour is there).
  /// All of them are exact for a quadratic f.
  Vec3d indexGradient(VertexId v) const {
    const VoxelIndex c = domain_.indexOf(v);
    const int at[3] = {c.i, c.j, c.k};
    double g[3] = {0, 0, 0};
    const double here = u_[v] * u_[v];
    for (int a = 0; a < 3; ++a) {
      auto sample = [&](int offset, double& f) {
        int p[3] = {at[0], at[1], at[2]};
        p[a] += offset;
        return fieldAt(p[0], p[1], p[2], f);
      };
      double minus = 0, plus = 0, minus2 = 0, plus2 = 0;
      const bool hasMinus = sample(-1, minus), hasPlus = sample(1, plus);
      if (hasMinus && hasPlus)
        g[a] = 0.5 * (plus - minus);
      else if (hasPlus)
        g[a] = sample(2, plus2) ? 0.5 * (-3.0 * here + 4.0 * plus - plus2) : plus - here;
      else if (hasMinus)
        g[a] = sample(-2, minus2) ? 0.5 * (3.0 * here - 4.0 * minus + minus2) : here - minus;
    }
    return {g[0], g[1], g[2]};
  }

  /// Unit descent direction -G^-1 grad u / |.| at x and the interpolated u.
  bool direction(Vec3d x, Vec3d& unit, double& u, PathFallback& why) const {
    CellSample cell;
    if (!locate(domain_, geometry_.physicalPointToIndex(x), cell)) {
      why = PathFallback::LeavesImage;
      return false;
    }
    Sym3 g;
    Vec3d gradIndex;
    u = 0.0;
    // Over the corners of the smallest face that holds x (a voxel centre
    // next to an excluded voxel stays usable despite rounding), weights
    // renormalised.
    int moving;
    const int face = detail::faceCorners(cell, moving);
    double total = 0.0;
    for (int n = 0; n < 8; ++n) {
      if (!((face >> n) & 1)) continue;
      const VertexId c = cell.corner[n];
      if (!reached_(c)) {
        why = PathFallback::LeavesDomain;
        return false;
      }
      u += cell.weight[n] * u_[c];
      g.add(cell.weight[n], metric_[c]);
      gradIndex = gradIndex + cell.weight[n] * indexGradient(c);
      total += cell.weight[n];
    }
    if (!(total > 0.0)) {
      why = PathFallback::LeavesDomain;
      return false;
    }
    u /= total;
    gradIndex = (1.0 / total) * gradIndex;
    g.xx /= total, g.xy /= total, g.xz /= total, g.yy /= total, g.yz /= total, g.zz /= total;
    // grad_x f = D S^-1 grad_ijk f (x = origin + D S ijk).
    const auto& s = geometry_.spacing;
    Vec3d gradient =
        geometry_.indexToPhysicalOffset(gradIndex.x / (s[0] * s[0]), gradIndex.y / (s[1] * s[1]),
                                        gradIndex.z / (s[2] * s[2]));
    // grad u = grad(u^2) / 2u; u > 0 here, since a source corner within
    // one step ends the path before.
    gradient = (u > 0.0 ? 0.5 / u : 0.0) * gradient;
    Vec3d d;
    // An exact distance field has |grad u|_{G^-1} = 1 (the eikonal
    // equation); below 0.1 the field is flat there (a ridge, a plateau).
    if (!g.solve(gradient, d) || !(dot(gradient, d) >= 0.01)) {
      why = PathFallback::GradientVanishes;
      return false;
    }
    unit = (-1.0 / norm(d)) * d;
    return true;
  }

  /// One Heun step from x; `next` lies in a valid cell.
  bool heunStep(Vec3d x, Vec3d& next, double& unext, PathFallback& why) const {
    Vec3d k1, k2;
    double u0, u1;
    if (!direction(x, k1, u0, why)) return false;
    if (!direction(clampToImage(geometry_, x + step_ * k1), k2, u1, why)) return false;
    // Stages pointing apart by more than 90 degrees: the step straddles a
    // ridge or a kink of the field.
    const Vec3d sum = k1 + k2;
    if (dot(k1, k2) <= 0.0 || norm(sum) == 0.0) {
      why = PathFallback::GradientVanishes;
      return false;
    }
    next = clampToImage(geometry_, x + (step_ / norm(sum)) * sum);
    // Pushed into the border: the descent points out of the image.
    if (norm(next - x) < 0.5 * step_) {
      why = PathFallback::LeavesImage;
      return false;
    }
    if (!sampleDistance(next, unext, why)) return false;
    // A new point keeps closer to the region than rounding allows for the
    // points it starts from; and both ends in the region is not enough: a
    // step may cut a corner of the cells around an excluded voxel.
    if (!detail::pointInRegion(domain_, geometry_.physicalPointToIndex(next), reached_, detail::kNewPointOnPlane) ||
        !inRegion(x, next)) {
      why = PathFallback::LeavesDomain;
      return false;
    }
    return true;
  }

  /// The segment between the physical points a and b keeps to the region of
  /// the reached domain voxels (and the contacts the connectivity joins).
  bool inRegion(Vec3d a, Vec3d b) const {
    return detail::segmentInRegion(domain_, geometry_.physicalPointToIndex(a), geometry_.physicalPointToIndex(b),
                                   reached_);
  }

  /// u at x when x's cell is valid.
  bool sampleDistance(Vec3d x, double& u, PathFallback& why) const {
    CellSample cell;
    if (!locate(domain_, geometry_.physicalPointToIndex(x), cell)) {
      why = PathFallback::LeavesImage;
      return false;
    }
    u = 0.0;
    int moving;
    const int face = detail::faceCorners(cell, moving);
    double total = 0.0;
    for (int n = 0; n < 8; ++n) {
      if (!((face >> n) & 1)) continue;
      const VertexId c = cell.corner[n];
      if (!reached_(c)) {
        why = PathFallback::LeavesDomain;
        return false;
      }
      u += cell.weight[n] * u_[c];
      total += cell.weight[n];
    }
    if (!(total > 0.0)) {
      why = PathFallback::LeavesDomain;
      return false;
    }
    u /= total;
    return true;
  }

  /// G interpolated at x over the domain corners, or the mean of the two
  /// end points' fields when the midpoint's cell is not fully inside.
  Sym3 metricAt(Vec3d x) const {
    CellSample cell;
    Sym3 g;
    if (!locate(domain_, geometry_.physicalPointToIndex(x), cell)) return g;
    double total = 0.0;
    for (int n = 0; n < 8; ++n)
      if (cell.weight[n] > 0.0 && domain_.contains(cell.corner[n])) {
        g.add(cell.weight[n], metric_[cell.corner[n]]);
        total += cell.weight[n];
      }
    if (total > 0.0 && total < 1.0) {
      g.xx /= total, g.xy /= total, g.xz /= total, g.yy /= total, g.yz /= total, g.zz /= total;
    }
    return g;
  }

  TracedPath& finish(TracedPath& path) const {
    std::vector<Vec3d>& p = path.points;
    std::reverse(p.begin(), p.end());
    // A point is smoothed only where its segments to its neighbours (the
    // one before already decided) stay in the region.
    for (int pass = 0; pass < options_.smoothingPasses && p.size() > 2; ++pass) {
      const std::vector<Vec3d> before = p;
      for (std::size_t n = 1; n + 1 < p.size(); ++n) {
        const Vec3d smoothed = 0.25 * before[n - 1] + 0.5 * before[n] + 0.25 * before[n + 1];
        if (inRegion(p[n - 1], smoothed) && inRegion(smoothed, p[n + 1])) p[n] = smoothed;
      }
    }
    if (options_.refine)
      path.refinement = detail::refineGeodesicPath(domain_, metric_, u_, p, options_.refinement, progress_, kHalf, kHalf);
    for (std::size_t n = 1; n < p.size(); ++n) {
      const Vec3d d = p[n] - p[n - 1];
      path.euclideanLength += norm(d);
      path.metricLength += std::sqrt(std::max(0.0, metricAt(0.5 * (p[n] + p[n - 1])).quadraticForm(d)));
    }
    return path;
  }

  const VoxelGridDomain& domain_;
  const GridGeometry& geometry_;
  const RiemannianMetric& metric_;
  const std::vector<double>& u_;
  detail::ReachedVoxel reached_;  // the voxels of the domain the propagation reached
  const PropagationResult& result_;
  PathTracingOptions options_;
  InterruptScope& progress_;
  double step_ = 0.0;
};

}  // namespace

TracedPath traceGeodesicPath(const VoxelGridDomain& domain, const RiemannianMetric& metric,
                             const PropagationResult& result, VertexId target,
                             const PathTracingOptions& options) {
  if (metric.size() != domain.vertexCount() || result.distance.size() != domain.vertexCount() ||
      result.predecessor.size() != domain.vertexCount())
    throw std::invalid_argument("metric, propagation result and domain differ in size");
  if (target >= domain.vertexCount())
    throw std::invalid_argument("target vertex " + std::to_string(target) + " is out of range");
  if (!result.hasPredecessors) throw std::invalid_argument(detail::kNoPredecessorsMessage);
  if (!(options.stepFraction > 0.0 && options.stepFraction <= 1.0))
    throw std::invalid_argument("path step fraction must be in (0, 1]");
  if (options.fallbackVertices < 1 || options.noDescentSteps < 1 || !(options.stepBudgetFactor > 0.0) ||
      options.smoothingPasses < 0)
    throw std::invalid_argument("path tracing options out of range");
  if (options.refine && !(options.refinement.spacingFraction > 0.0 && options.refinement.spacingFraction <= 0.5 &&
                          options.refinement.maxIterations >= 0 && options.refinement.maxHalvings >= 0 &&
                          options.refinement.tolerance > 0.0 && options.refinement.energyTolerance >= 0.0))
    throw std::invalid_argument("path refinement options out of range");
  InterruptScope progress(options.interrupter, "path tracing", PathTracer::kTracingSteps, options.progressInterval);
  TracedPath path = PathTracer(domain, metric, result, options, progress).trace(target);
  progress.finish();
  return path;
}

double interpolateAtPoint(const VoxelGridDomain& domain, const std::vector<float>& values, Vec3d point) {
  if (values.size() != domain.vertexCount()) throw std::invalid_argument("value image and domain differ in size");
  constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
  CellSample cell;
  if (!locate(domain, domain.geometry().physicalPointToIndex(point), cell)) return kNan;
  // The corners of the smallest face that holds the point: a weight of a
  // rounding error on a voxel outside the domain does not count.
  int moving;
  const int face = detail::faceCorners(cell, moving);
  auto inDomain = [&](VertexId v) { return domain.contains(v); };
  double sum = 0.0, total = 0.0;
  bool inside = true;
  for (int n = 0; n < 8 && inside; ++n) {
    if (!((face >> n) & 1)) continue;
    inside = domain.contains(cell.corner[n]);
    sum += cell.weight[n] * values[cell.corner[n]];
    total += cell.weight[n];
  }
  if (inside) return total > 0.0 ? sum / total : kNan;
  // On a contact the connectivity joins: linear between its two voxels.
  int from, to;
  double t;
  if (detail::onJoinedContact(domain, cell, face, moving, inDomain, from, to, t))
    return (1.0 - t) * values[cell.corner[from]] + t * values[cell.corner[to]];
  return kNan;
}

TracedPath discreteGeodesicPath(const VoxelGridDomain& domain, const PropagationResult& result, VertexId target) {
  if (result.distance.size() != domain.vertexCount() || result.predecessor.size() != domain.vertexCount())
    throw std::invalid_argument("propagation result and domain differ in size");
  if (target >= domain.vertexCount())
    throw std::invalid_argument("target vertex " + std::to_string(target) + " is out of range");
  TracedPath path;
  path.discrete = predecessorPath(result, target);
  if (path.discrete.empty()) return path;
  path.geodesicLength = result.distance[target];
  for (VertexId v : path.discrete) path.points.push_back(domain.physicalPoint(v));
  path.discretePoints = path.points.size();
  for (std::size_t p = 1; p < path.points.size(); ++p) path.euclideanLength += norm(path.points[p] - path.points[p - 1]);
  path.metricLength = std::numeric_limits<double>::quiet_NaN();
  return path;
}

PathSamples sampleAlongPath(const VoxelGridDomain& domain, const std::vector<float>& values,
                            const std::vector<Vec3d>& points) {
  PathSamples samples;
  for (const Vec3d& p : points) samples.values.push_back(static_cast<float>(interpolateAtPoint(domain, values, p)));
  double sum = 0.0, length = 0.0;
  for (std::size_t n = 1; n < points.size(); ++n) {
    const double l = norm(points[n] - points[n - 1]);
    sum += 0.5 * l * (static_cast<double>(samples.values[n - 1]) + samples.values[n]);
    length += l;
  }
  if (points.size() == 1)
    samples.lengthWeightedMean = samples.values[0];
  else
    samples.lengthWeightedMean = length > 0.0 ? sum / length : std::numeric_limits<double>::quiet_NaN();
  return samples;
}

const char* pathFallbackName(PathFallback f) {
  switch (f) {
    case PathFallback::GradientVanishes: return "gradient_vanishes";
    case PathFallback::LeavesImage: return "leaves_image";
    case PathFallback::LeavesDomain: return "leaves_domain";
    case PathFallback::NoDescent: return "no_descent";
    case PathFallback::StepLimit: return "step_limit";
  }
  return "?";
}

}  // namespace stvd
