// Refinement of a path on a voxel grid into a discrete geodesic of the
// metric itself (docs/paths.md, "Refinement"). A path traced down a computed
// distance field inherits that field's errors, and a geodesic's position is
// ill-conditioned with respect to its length: a few percent of distance
// error move it by voxels. Minimising the path's own discrete energy with
// the end points fixed removes the distance field from the result; only the
// path's starting position (which local minimum) still comes from it.
#pragma once

#include <cstddef>
#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {

/// The iteration. The polyline x_0 .. x_N (physical points, x_0 and x_N
/// fixed) is first resampled to N segments of equal metric length, N chosen
/// so that no segment spans more than `spacingFraction` voxel along any index
/// axis. Then it minimises the discrete energy
///   E = sum_i d_i^T G(m_i) d_i,  d_i = x_{i+1} - x_i,  m_i = (x_i + x_{i+1}) / 2,
/// G interpolated trilinearly at the midpoints, whose minimisers are
/// discrete geodesics with equal metric spacing. Each iteration solves
/// H delta = -grad E with the block-tridiagonal matrix H (3 x 3 blocks
/// 2(G(m_{i-1}) + G(m_i)) on the diagonal, -2 G(m_i) beside it: the Hessian
/// of E for a constant metric, a Gauss-Newton / Sobolev preconditioner) in
/// O(N), then backtracks (halving, at most `maxHalvings` times) from twice
/// the previous iteration's step, at most the full step, until E decreases.
///
/// Constraints: a coordinate on the image box (the box of voxel centres)
/// whose descent points out of it is fixed for the step, other points are
/// clamped into the box. A point may move only where every cell corner
/// with a non-zero trilinear weight is in the domain and reached (finite
/// distance), and only if every point of its segments is such a point
/// (tested exactly, cell piece by cell piece); otherwise it keeps its
/// position, is fixed, and the step is solved again for the others. So the
/// refined path never enters a voxel outside the domain. Points of the
/// starting path that already sit next to such voxels (the predecessor
/// chain's diagonal steps past a masked voxel's corner) stay where they
/// are, and so do, in effect, their neighbours.
///
/// Stops when the largest point move of an accepted step is below
/// `tolerance` voxel, when the step decreased E by less than
/// `energyTolerance` times E, when no step decreases E, or after
/// `maxIterations`.
struct PathRefinementOptions {
  /// Largest extent of a segment along any index axis after resampling
  /// (voxels), in (0, 0.5].
  double spacingFraction = 0.4;
  int maxIterations = 200;
  int maxHalvings = 30;
  /// Largest point move (voxels, index infinity-norm) below which the
  /// iteration has converged.
  double tolerance = 1e-2;
  /// Relative decrease of E in an accepted step below which the iteration
  /// has converged: a path displaced sideways by delta over a metric length
  /// L has a relative excess energy of about (delta / L)^2, so 1e-8 stands
  /// for about 1e-4 L. Without it, steps across the kinks of the
  /// trilinear metric (cell faces) kept moving points by hundredths of a
  /// voxel at no gain, up to maxIterations.
  double energyTolerance = 1e-8;
  /// Hears refineGeodesicPath as one operation, "path refinement": 0 %,
  /// the share of maxIterations done at least every progressInterval
  /// seconds (looked at in every iteration and every halving of its step),
  /// 100 %. Stopped, it throws Cancelled and leaves `points` as they were.
  /// Within traceGeodesicPath the tracing's interrupter is used instead.
  /// Not owned.
  Interrupter* interrupter = nullptr;
  double progressInterval = kDefaultInterruptInterval;
};

struct PathRefinementReport {
  std::size_t iterations = 0;
  /// Stopped by the tolerance or because no step decreased the energy
  /// (not by maxIterations).
  bool converged = false;
  double initialEnergy = 0.0;
  double finalEnergy = 0.0;
  /// Point moves refused by the domain constraint, over all steps.
  std::size_t heldMoves = 0;
};

/// Refines `points` in place (x_0 and x_N kept). `distance` marks reached
/// vertices (finite values); it is not otherwise used. Leaves `points`
/// unchanged when it has fewer than 2 points or its end points coincide.
/// Throws std::invalid_argument when sizes disagree or the options are out
/// of range, and Cancelled (with `points` unchanged) when
/// options.interrupter asks to stop.
PathRefinementReport refineGeodesicPath(const VoxelGridDomain& domain, const RiemannianMetric& metric,
                                        const std::vector<double>& distance, std::vector<Vec3d>& points,
                                        const PathRefinementOptions& options = {});

}  // namespace stvd
