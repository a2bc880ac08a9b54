// Geodesic paths from a propagation's result back to its sources: the
// discrete predecessor chain, and a continuous curve that descends the
// distance field along the characteristic direction -G^-1 grad u and is then
// refined into a discrete geodesic of the metric (docs/paths.md).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/predecessor_path.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/path_refinement.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {

/// Why the gradient descent handed over to the predecessor chain.
enum class PathFallback {
  GradientVanishes,  ///< |G^-1 grad u| too small, or the two Heun stages disagree by > 90 degrees
  LeavesImage,       ///< the descent points out of the image (a step clamped to the border shrank below half)
  LeavesDomain,      ///< a sample cell has a corner outside the domain or not reached
  NoDescent,         ///< the interpolated distance failed to decrease for several steps
  StepLimit,         ///< the step budget ran out
};
inline constexpr int kPathFallbackKinds = 5;

/// Continuous path tracing on a voxel grid.
///
/// The metric G and the gradient of the squared distance f = u^2 are
/// interpolated trilinearly between voxel centres; grad f at a voxel is the
/// central difference of f (second-order one-sided where a neighbour is
/// outside the domain, the image or not reached). f, unlike u, is smooth at
/// the sources (u^2 = (x-s)^T G (x-s) near a source s), and these
/// differences are exact for a quadratic f, so the direction stays accurate
/// close to the sources and on the image border, where differences of the
/// cone u fail. The path follows
/// dx/ds = -G^-1 grad u / |G^-1 grad u|, grad u = grad f / 2u (unit speed
/// in millimetres), integrated with Heun's method (explicit trapezoid) at a
/// fixed physical step. Points that a step would carry out of the box of
/// voxel centres are clamped onto it (the path slides along the image
/// border). Tracing stops when the curve comes within one step
/// of a source voxel, which becomes the last point. Wherever the descent is
/// not trustworthy (see PathFallback), the path jumps to the corner of the
/// current cell with the smallest distance and follows the predecessor
/// chain for `fallbackVertices` vertices before it tries the gradient
/// again, so it always ends at a source and never enters a cell with a
/// corner outside the domain.
struct PathTracingOptions {
  /// Step length as a fraction of the smallest grid spacing.
  double stepFraction = 0.25;
  /// Vertices of the predecessor chain followed after a fallback.
  int fallbackVertices = 2;
  /// Consecutive steps without a decrease of the interpolated distance
  /// before NoDescent.
  int noDescentSteps = 4;
  /// Total Heun steps allowed, as a multiple of (length of the discrete
  /// path) / step; when exhausted the rest of the path is discrete.
  double stepBudgetFactor = 4.0;
  /// Passes of a [1/4, 1/2, 1/4] moving average over the interior points
  /// (end points fixed) after tracing; 0 = none.
  int smoothingPasses = 0;
  /// Refine the traced (and smoothed) curve into a discrete geodesic of the
  /// metric (refineGeodesicPath), so that its position no longer depends
  /// on the distance field's errors.
  bool refine = true;
  PathRefinementOptions refinement;
  /// Hears traceGeodesicPath as one operation, "path tracing": 0 %, the
  /// descent up to 50 % (by how far the distance has come down from the
  /// target's), the refinement up to 100 % (by its iterations), at least
  /// every progressInterval seconds. Stopped, traceGeodesicPath throws
  /// Cancelled: a path that does not reach a source is no path. Not owned.
  Interrupter* interrupter = nullptr;
  double progressInterval = kDefaultInterruptInterval;
};

struct TracedPath {
  /// Physical points (the grid's frame, millimetres), from the source end
  /// (first) to the target (last). Empty when the target was not reached.
  std::vector<Vec3d> points;
  /// The discrete path of the same target (source first).
  std::vector<VertexId> discrete;
  /// u(target): the geodesic distance.
  double geodesicLength = kUnreachable;
  /// Sum of |x_{n+1} - x_n| over the polyline (mm).
  double euclideanLength = 0.0;
  /// Sum of sqrt(d^T G d), d = x_{n+1} - x_n, G interpolated at the segment's
  /// midpoint: the traced curve measured with the metric (mm).
  double metricLength = 0.0;
  std::size_t gradientSteps = 0;
  /// Points that came from the predecessor chain (after fallbacks).
  std::size_t discretePoints = 0;
  /// The refinement's iterations and energies (all zero without it).
  PathRefinementReport refinement;
  /// Fallbacks by kind, indexed by PathFallback.
  std::size_t fallbacks[kPathFallbackKinds] = {0, 0, 0, 0, 0};
  std::size_t fallbackCount() const {
    std::size_t n = 0;
    for (std::size_t f : fallbacks) n += f;
    return n;
  }
};

/// Traces the path from `target` back to the sources of `result` (vertices
/// of distance 0) over `domain` under `metric` (the field the propagation
/// used). Throws std::invalid_argument when sizes disagree, the target is
/// out of range or the options are out of range, and Cancelled when
/// options.interrupter asks to stop.
TracedPath traceGeodesicPath(const VoxelGridDomain& domain, const RiemannianMetric& metric,
                             const PropagationResult& result, VertexId target,
                             const PathTracingOptions& options = {});

/// Trilinear interpolation of a per-voxel scalar (e.g. FA) at a physical
/// point of the domain's region; on a contact that the domain's
/// connectivity joins, linear between its two voxels. NaN outside the box of
/// voxel centres or outside the region (a corner with a non-zero weight
/// outside the domain; within 1e-4 voxel of a cell face a point counts as
/// on it, for the rounding of single-precision direction cosines).
double interpolateAtPoint(const VoxelGridDomain& domain, const std::vector<float>& values, Vec3d point);

/// The discrete path of `target` in the form of a traced one: the voxel
/// centres of its predecessor chain (predecessorPath) as points, its
/// geodesic and Euclidean lengths; no metric length (NaN), gradient steps,
/// fallbacks or refinement. Empty when the target was not reached. Takes no
/// interrupter: one step per vertex of the path (microseconds for a path
/// across the sample brain).
TracedPath discreteGeodesicPath(const VoxelGridDomain& domain, const PropagationResult& result, VertexId target);

/// A per-voxel scalar (e.g. FA) along a path: its value at each point
/// (interpolateAtPoint) and their mean weighted by the path's length
/// (trapezoid rule; the value itself for a single point; NaN when a value
/// is missing or the path has no length).
struct PathSamples {
  std::vector<float> values;
  double lengthWeightedMean = 0.0;
};
PathSamples sampleAlongPath(const VoxelGridDomain& domain, const std::vector<float>& values,
                            const std::vector<Vec3d>& points);

/// Text name of a fallback kind: "gradient_vanishes", "leaves_image", ...
const char* pathFallbackName(PathFallback f);

}  // namespace stvd
