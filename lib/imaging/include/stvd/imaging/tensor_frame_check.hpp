// Whether a tensor volume's components are given in the frame of its image
// axes. A tensor image whose voxels were reordered without its components
// being rotated (NiBabel's as_closest_canonical, a flip or a transpose of
// the array, a header edited by hand) is still a volume of plausible
// tensors: every eigenvalue is right, only the principal directions point
// the wrong way, and distances come out several per cent, in places tens of
// per cent, off. The component-order check (tensor_plausibility.hpp) cannot
// see it.
//
// What can see it is the anatomy, as MRtrix's dwigradcheck does for
// gradient tables: white-matter tracts are long and coherent, and principal
// directions that follow them give long streamlines, while directions that
// are flipped or permuted relative to the voxel grid cross the tracts and
// give short, incoherent ones. So deterministic streamlines of the
// principal eigenvector are tracked from the same high-FA seeds under each
// of the 48 signed permutations of the voxel axes, and the mean lengths
// compared: the frame as read should win by a margin. A transform and its
// negative give the same tensors (T D T^T = (-T) D (-T)^T), so the 48 are 24
// distinguishable frames; the one with fewer flipped axes names each.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "stvd/types.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

/// A signed permutation of the voxel axes i, j, k, as a correction of the
/// components read: corrected axis a is `sign[a]` times read axis
/// `axis[a]` (so a tensor D becomes T D T^T, a direction e becomes T e).
struct AxisTransform {
  std::array<int, 3> axis{0, 1, 2};
  std::array<int, 3> sign{1, 1, 1};
  bool isIdentity() const { return axis == std::array<int, 3>{0, 1, 2} && sign == std::array<int, 3>{1, 1, 1}; }
  bool operator==(const AxisTransform& o) const { return axis == o.axis && sign == o.sign; }
};

/// "(-i, j, k)": the corrected components' axes in terms of the read ones.
std::string axisTransformText(const AxisTransform& t);
/// In words: "as read", "flipped along i", "with i and j swapped",
/// "with i and j swapped and flipped along k", "with the axes cycled to
/// (j, k, i)".
std::string axisTransformWords(const AxisTransform& t);
/// The 24 distinguishable transforms (each the one of T and -T with fewer
/// flipped axes), the identity first.
std::vector<AxisTransform> distinguishableAxisTransforms();
/// The distinguishable transform that gives the same tensors as `t` (t or -t).
AxisTransform canonicalAxisTransform(const AxisTransform& t);
/// T D T^T, with D in the voxel frame.
SymTensor3 transformTensor(const SymTensor3& d, const AxisTransform& t);

struct TensorFrameCheckOptions {
  double seedFa = 0.4;             ///< streamlines start in voxels of at least this FA
  double stopFa = 0.2;             ///< and stop below this FA
  double maxTurnDegrees = 45.0;    ///< or where the direction turns more than this in one step
  double stepVoxels = 0.5;         ///< step, in voxels of the smallest spacing
  double maxLengthMm = 200.0;      ///< each way
  std::size_t maxSeeds = 2000;     ///< seeds spread evenly over the eligible voxels
  std::size_t minSeeds = 100;      ///< fewer: inconclusive
  /// A frame other than the one read is reported as a mismatch when its
  /// mean streamline is at least this many times as long as the one read,
  /// and at least minMeanMm long.
  double mismatchRatio = 1.3;
  double minMeanMm = 8.0;
};

/// How the check came out.
enum class TensorFrameVerdict {
  Consistent,    ///< the frame as read fits best
  Mismatch,      ///< another frame fits clearly better
  Inconclusive,  ///< too few high-FA voxels, or no frame fits clearly better
  NotChecked,    ///< not run (metric tensors: their principal direction is the costly one)
};
/// "consistent", "mismatch", "inconclusive", "not checked".
std::string tensorFrameVerdictName(TensorFrameVerdict verdict);

struct TensorFrameTrial {
  AxisTransform transform;
  double meanLengthMm = 0.0;
};

struct TensorFrameCheck {
  TensorFrameVerdict verdict = TensorFrameVerdict::Inconclusive;
  std::size_t seeds = 0;
  /// Every distinguishable frame, best first (ties: in the order of
  /// distinguishableAxisTransforms, so the frame as read wins a tie).
  std::vector<TensorFrameTrial> trials;
  double readMeanMm = 0.0;  ///< the frame as read (identity)
  /// The best frame, and its mean over the one read (1 when it is the one
  /// read); when the one read is best, `margin` is its mean over the
  /// runner-up's.
  AxisTransform best;
  double bestMeanMm = 0.0;
  double ratio = 1.0;
  double margin = 1.0;
  std::string reason;  ///< why inconclusive, "" otherwise
};

/// Runs the check on tensors in LPS (as stvd holds them) on `geometry`,
/// restricted to `domain` (empty: every voxel). Diffusion tensors: the
/// principal eigenvector is the direction of fastest diffusion. Single
/// thread, deterministic; 0.03 s of CPU on the shipped brain, half the time
/// its file takes to read.
TensorFrameCheck checkTensorFrame(const std::vector<SymTensor3>& tensorsLps, const GridGeometry& geometry,
                                  const std::vector<std::uint8_t>& domain, const TensorFrameCheckOptions& options = {});

/// One line for a report: e.g. "consistent: the frame as read fits best
/// (mean streamline 31.2 mm, 2.4 times the runner-up's (-i, j, k)), 2,000
/// seeds".
std::string tensorFrameCheckSummary(const TensorFrameCheck& check);

}  // namespace stvd::imaging
