// The direction-dependent cost of an FOD and the convexified (Finsler) norm
// the methods compute (issue 35; docs/fod.md, "The cost" and "The
// convexified norm").
//
// The cost of moving along v at voxel x is F(x, v) = |v| c(x, v/|v|) with
//
//   c(x, u) = 1 / rho(x, u),   rho(x, u) = max(floor, min(1, a(x, u) / a_max(x)))^power
//
// a(x, u) the FOD's amplitude and a_max(x) its largest over the sampling
// directions and the FOD's refined maxima (below): the best direction of every voxel costs 1 per mm,
// none costs less, none more than floor^-power, and a voxel whose FOD is
// nowhere positive (outside the fit's mask) costs floor^-power everywhere.
//
// The unit ball {v : F(x, v) <= 1} is the star-shaped set of radius
// rho(x, u) along u: not convex where lobes cross, and a straight segment
// under F is then longer than a zig-zag along the lobes, which a path can
// always make. The methods compute instead the norm F* whose unit ball is
// the convex hull of F's: F*(v) = min { sum l_i : v = sum l_i w_i, l_i >= 0 }
// over the points w_i = rho(x, g_i) g_i of F's ball along the sampling
// directions g_i and along the FOD's refined maxima (and, with the default
// sampling, along the directions of a finer set near the maxima:
// FodPeakCaps). F* is a norm
// (positive, 1-homogeneous, convex, symmetric as an FOD is); F* <= F along
// every sampling direction, and a straight step under F* is as long as a
// zig-zag along the w_i measured under F, which a path can make: F* is what
// paths achieve, never less. F* = F along the FOD's largest maxima (radius
// 1, the largest there is). Along directions between samples F* can exceed
// F (the hull of the samples lies inside the hull of the whole ball): then
// F* is longer than the best zig-zag, never shorter (docs/fod.md gives the
// sizes).
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "stvd/imaging/fod_field.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

struct FodCostOptions {
  /// The smallest normalised amplitude counted: the cost of any direction
  /// is at most floor^-power times that of the voxel's best one.
  double floor = 0.1;
  /// The exponent of the normalised amplitude.
  double power = 1.0;
  /// Throws std::invalid_argument unless 0 < floor <= 1 and 0 < power <= 8.
  void validate() const;
};

/// The vertices of an icosahedron subdivided `subdivisions` times (each
/// triangle into four), on the unit sphere: 12, 42, 162, 642, 2562, ...
/// directions, antipodally symmetric.
std::vector<Vec3d> icosphereDirections(int subdivisions);

/// The unit directions (LPS) of the 26 neighbours of a voxel, in the order
/// of the offsets (di, dj, dk) with dk slowest, (0, 0, 0) left out.
std::vector<Vec3d> neighbourDirections26(const GridGeometry& geometry);

/// The icosphere of the default sampling directions.
inline constexpr int kFodSamplingSubdivisions = 3;

/// The sampling directions of the cost: icosphereDirections(subdivisions)
/// (642 for 3, 2562 for 4) turned with the grid's axes (the icosphere's x,
/// y, z along the unit index axes i, j, k), and the 26 neighbour directions
/// of the grid: the same directions relative to the voxels whatever the
/// image's rotation, so that an FOD in the voxel frame gives the same table
/// under any rotated or flipped affine.
std::vector<Vec3d> defaultFodSamplingDirections(const GridGeometry& geometry, int subdivisions = kFodSamplingSubdivisions);

/// Points of F's unit ball where its hull needs them, per voxel: the
/// directions of a denser set that lie within `radius` of a sampling
/// direction where one of the FOD's maxima was found (a cap around each
/// lobe, where the hull's surface is curved: its flanks) and whose
/// normalised amplitude is above the floor (below it the point is on the
/// floor's sphere, which the coarse set covers). The maximum's refinement
/// starts from the best of its cap's directions within a spacing of the
/// sampling, by steps from half the dense set's spacing. They are points
/// of F's ball, so F* <= F still holds at each and the hull lies inside the
/// converged one: F* is never below the converged F* (but by what the
/// maxima's refinement to 1e-3 rad leaves, 1e-4 near a fibre). Empty
/// directions or radius 0: no caps.
struct FodPeakCaps {
  /// The dense directions (LPS, any length; every one with its opposite).
  std::vector<Vec3d> directions;
  /// The caps' angular radius (radians).
  double radius = 0.0;
};

/// A sampling of F's unit ball: fixed directions and caps around the maxima.
struct FodSampling {
  std::vector<Vec3d> directions;
  FodPeakCaps caps;
};

/// The defaults of adaptiveFodSampling, the tables' default sampling: the
/// coarse icosphere of 162 directions, caps of the 642 of
/// kFodSamplingSubdivisions (the coarse ones among them) within 50 degrees
/// of the maxima (40 cut the flanks of broad lobes, l <= 4, crossing at 45
/// degrees): the same 668 directions as defaultFodSamplingDirections,
/// the fine ones evaluated only near the lobes (docs/fod.md, "A sampling
/// adapted to each voxel": the same F* to the measurements' precision, for
/// three quarters of the table's time).
inline constexpr int kFodCoarseSubdivisions = 2;
inline constexpr int kFodCapSubdivisions = kFodSamplingSubdivisions;
inline constexpr double kFodCapRadiusDegrees = 50.0;

/// A sampling adapted to each voxel: defaultFodSamplingDirections(geometry,
/// coarse) (icosphere turned with the grid, and the 26 neighbour
/// directions, so that F* <= F along them exactly) and caps of
/// radius `capRadiusDegrees` of icosphereDirections(dense) turned with the
/// grid as well, so that the same FOD relative to the voxels gives the same
/// table whatever the image's rotation.
FodSampling adaptiveFodSampling(const GridGeometry& geometry, int coarse = kFodCoarseSubdivisions,
                                int dense = kFodCapSubdivisions, double capRadiusDegrees = kFodCapRadiusDegrees);

/// The sampling of the tables the tool and the Python package compute.
inline FodSampling defaultFodSampling(const GridGeometry& geometry) { return adaptiveFodSampling(geometry); }

/// Voxel v's unit ball {u : F(x, u) <= 1} as the convexification sees it:
/// the points rho(x, g_i) g_i along the sampling directions g_i, and
/// rho(x, p) p = p along each of the FOD's maxima p (refined beyond the
/// sampling, so that F* = F = 1 there exactly).
struct FodUnitBall {
  /// The FOD's largest amplitude, its refined maxima included; not
  /// positive for a voxel whose FOD is nowhere positive (then every radius
  /// is floor^power and there are no peaks).
  double amplitudeMax = 0.0;
  /// Unit directions (LPS) of the FOD's local maxima over the sampling
  /// directions whose normalised amplitude is at least the floor, each
  /// refined to its maximum on the sphere (to 1e-3 rad): both antipodes.
  std::vector<Vec3d> peaks;
  /// rho(x, g_i) g_i for every sampling direction, then p for every peak,
  /// then the caps' points (FodPeakCaps) if the sampler has caps.
  std::vector<Vec3d> points;

  // Scratch space of unitBall, kept to spare allocations.
  std::vector<double> rowAmplitudes, peakValues, capAmplitudes;  // capAmplitudes: per cap row
  std::vector<int> peakOfDirection, capTaken;
  std::vector<unsigned char> capSeen;
};

/// An FOD's cost sampled along fixed unit directions (LPS): the spherical
/// harmonics along them evaluated once, then per voxel a matrix product.
class FodCostSampler {
 public:
  /// `directions` must surround the origin (their cone is all of R^3), as
  /// every set above does.
  FodCostSampler(const FodField& field, std::vector<Vec3d> directions, FodCostOptions options = {},
                 FodPeakCaps caps = {});
  /// The same with a sampling's directions and caps.
  FodCostSampler(const FodField& field, FodSampling sampling, FodCostOptions options = {})
      : FodCostSampler(field, std::move(sampling.directions), options, std::move(sampling.caps)) {}

  const std::vector<Vec3d>& directions() const { return directions_; }
  const FodCostOptions& options() const { return options_; }
  /// The caps' dense directions (unit, LPS; none without caps) and radius.
  const std::vector<Vec3d>& capDirections() const { return capDirections_; }
  double capRadius() const { return capRadius_; }
  /// How many directions the ball is drawn from: the fixed ones and the
  /// caps' (668 for defaultFodSampling, as for the 668 fixed directions of
  /// defaultFodSamplingDirections).
  std::size_t directionCount() const { return directions_.size() + capDirections_.size(); }
  const FodField& field() const { return field_; }
  std::size_t voxelCount() const { return field_.geometry.voxelCount(); }

  /// Voxel v's unit ball (`ball` is reused to spare allocations): the
  /// amplitudes one row per direction up to sign (an FOD is even), and
  /// each antipodal pair of maxima refined once.
  void unitBall(std::size_t v, FodUnitBall& ball) const;
  /// The same ball the simple way, kept as the tests' reference: every
  /// direction's amplitude by its own row, every maximum refined on its
  /// own.
  void unitBallReference(std::size_t v, FodUnitBall& ball) const;
  /// F(x, d) for any non-zero d (LPS), with voxel v's amplitudeMax.
  double cost(std::size_t v, const Vec3d& d, double amplitudeMax) const;

 private:
  // simple: by evaluateShBasis's array of functions (the reference);
  // otherwise the same products summed as they are made (bit for bit).
  double amplitudeAt(const float* coefficients, const Vec3d& unitLps, bool simple) const;
  void amplitudesAt4(const float* coefficients, const Vec3d (&unitLps)[4], double (&out)[4]) const;
  Vec3d refinePeak(const float* coefficients, Vec3d start, double step, double* amplitude, bool simple) const;

  const FodField& field_;
  std::vector<Vec3d> directions_;
  FodCostOptions options_;
  std::vector<double> basis_;                  // directions x coefficients, row-major
  std::vector<std::vector<int>> neighbours_;   // sampling directions within 1.5 spacings
  double spacing_ = 0.0;                       // sqrt(4 pi / count), radians
  Vec3d axisI_{1, 0, 0}, axisJ_{0, 1, 0};      // the grid's unit i and j axes (LPS), for the refinement
  // unitBall: one row per direction up to sign, coefficient-major.
  std::size_t rows_ = 0;
  std::vector<double> basisByCoefficient_;     // coefficients x rows_
  std::vector<int> rowOf_;                     // direction -> its row
  std::vector<int> twin_;                      // the first earlier direction equal or opposite, or -1
  std::vector<std::vector<int>> neighbourRows_;  // neighbours_ by row
  // The caps: dense directions that are no sampling direction (nor the
  // opposite of one), their basis rows (the reference's, one per
  // direction), and for unitBall one row per direction up to sign
  // (row-major).
  std::vector<Vec3d> capDirections_;
  double capRadius_ = 0.0, capCos_ = 1.0;
  double capSpacing_ = 0.0;  // sqrt(4 pi / directionCount()), radians: the refinement's first step from a cap
  double nearCos_ = 1.0;     // cos(spacing_): a maximum's refinement starts from its cap's best direction this near
  std::vector<double> capBasis_;               // capDirections_ x coefficients
  std::size_t capRows_ = 0;
  std::vector<int> capRowDirection_;           // row -> its direction in capDirections_
  std::vector<double> capRowBasis_;            // capRows_ x coefficients
};

/// The gauge of the convex hull of the points w (which must surround the
/// origin: their cone is all of R^3) at v: min sum l_i over v = sum l_i
/// w_i, l_i >= 0, by the simplex method on this 3-row linear program. 0
/// for v = 0. Throws std::invalid_argument when the points do not surround
/// v's direction.
double convexHullGauge(const Vec3d* w, std::size_t count, const Vec3d& v);

/// convexHullGauge of one point set along many directions, faster and with
/// the same optimum (the same simplex start, every point's price checked at
/// the end): pricing first the points that entered a basis or priced best
/// before, all of them (in coordinate arrays) only when none of those
/// improves; and a direction inside the cone of a facet found before
/// answered by that facet (optimal for every direction in its cone). Not
/// thread-safe: one per thread.
class ConvexHullGauges {
 public:
  /// The points (they must surround the origin, as for convexHullGauge);
  /// forgets the facets and active points of the last set.
  void reset(const Vec3d* w, std::size_t count);
  /// The gauge at v (0 for v = 0); throws as convexHullGauge.
  double operator()(const Vec3d& v);

 private:
  double solve(const Vec3d& v);
  void activate(std::size_t j);
  struct Facet {
    double inv[9];  // the inverse of its basis (columns: three points)
  };
  std::size_t count_ = 0;
  std::vector<Vec3d> points_;
  std::vector<double> px_, py_, pz_;
  std::vector<unsigned char> active_;
  std::vector<int> activeList_;
  std::vector<Facet> facets_;
  double scale_ = 0.0, bigM_ = 0.0;
};

/// F* of every voxel along each query direction (LPS, unit or not), the
/// simple way: result[v * queries.size() + q], float, from
/// FodCostSampler::unitBallReference and convexHullGauge per direction.
/// Kept as the tests' reference for convexifiedFodTable (fod_metric.hpp),
/// the fast table every FOD metric is made of; with the queries among the
/// sampling directions, F* <= F along each.
std::vector<float> convexifiedFodNormsReference(const FodCostSampler& sampler, const std::vector<Vec3d>& queries);

}  // namespace stvd::imaging
