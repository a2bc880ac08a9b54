// From the tensors of an image to the Riemannian metric the propagation
// measures with, and the voxels that make up the domain.
//
// Diffusion tensors. Water diffuses easily along fibres, so a geodesic
// should find steps along the principal diffusion direction cheap. The
// inverse diffusion tensor as a Riemannian metric does exactly that
// (O'Donnell, Haker, Westin 2002). Scaling D voxelwise by its mean
// diffusivity MD = trace(D)/3 first removes the overall diffusivity and
// leaves only the shape: G = (D / MD)^-1, with eigenvalues MD/lambda_i. An
// isotropic voxel gets G = I (a step of v mm costs |v| mm); a step along the
// principal direction costs sqrt(MD/lambda_1), between 1/sqrt(3) and 1 of
// its Euclidean length.
//
// The adjugate alternative G = adj(D / MD) = det(D / MD) (D / MD)^-1
// (Fuster et al. 2016) multiplies the normalised inverse by det(D/MD) <= 1
// (equal to 1 only for an isotropic tensor), so anisotropic voxels are
// cheaper in every direction than isotropic ones: geodesics are drawn into
// coherent white matter more strongly.
//
// Repairs. Fitted tensors can be singular or indefinite (noise, partial
// volume, fits that clip eigenvalues). Diffusion tensors have their
// eigenvalues raised to the floor lambda_max / maxAnisotropy (100 unless
// given), so that lambda_max / lambda_min <= maxAnisotropy and every
// eigenvalue is positive; the metric's cost ratio between the dearest and
// the cheapest direction is then at most sqrt(maxAnisotropy). A metric given
// as such (TensorKind::Metric) is taken as it is: only an eigenvalue that is
// zero or negative is raised (to lambda_max / 100), unless maxAnisotropy is
// given, which then applies as for diffusion tensors. A tensor with a
// non-finite component, all six components zero, or no positive eigenvalue
// is outside the domain.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "stvd/system/interrupter.hpp"
#include "stvd/types.hpp"

namespace stvd::imaging {

enum class TensorKind {
  Diffusion,  ///< D: the metric is derived from it (see DiffusionMetric)
  Metric,     ///< G itself: the cost of a step v is sqrt(v^T G v)
};

enum class DiffusionMetric {
  NormalizedInverse,   ///< G = (D / MD)^-1
  NormalizedAdjugate,  ///< G = adj(D / MD)
};

/// "diffusion" or "metric".
std::optional<TensorKind> parseTensorKind(const std::string& name);
std::string tensorKindName(TensorKind kind);
/// "inverse" or "adjugate".
std::optional<DiffusionMetric> parseDiffusionMetric(const std::string& name);
std::string diffusionMetricName(DiffusionMetric metric);
/// A formula for humans, e.g. "G = (D/MD)^-1".
std::string metricFormula(TensorKind kind, DiffusionMetric metric);

/// The cap on diffusion tensors when none is given, and the floor of a
/// metric's non-positive eigenvalues.
inline constexpr double kDefaultMaxAnisotropy = 100.0;

struct MetricOptions {
  TensorKind kind = TensorKind::Diffusion;
  DiffusionMetric diffusionMetric = DiffusionMetric::NormalizedInverse;
  /// Cap on lambda_max / lambda_min of the tensor, >= 1. Unset: 100 for
  /// diffusion tensors, none for a metric (see the file's comment).
  std::optional<double> maxAnisotropy;
  /// When set, voxels whose tensor has a lower fractional anisotropy (of
  /// the tensor as read, before repairs) are outside the domain.
  std::optional<double> faThreshold;
};

/// How many voxels went where.
struct MetricVoxelCounts {
  std::uint64_t total = 0;
  std::uint64_t masked = 0;              ///< outside the mask(s)
  std::uint64_t nonFinite = 0;           ///< a NaN or infinite component: outside
  std::uint64_t zero = 0;                ///< all components zero: outside
  std::uint64_t noPositiveEigenvalue = 0;///< lambda_max <= 0: outside
  std::uint64_t belowFaThreshold = 0;    ///< outside
  std::uint64_t domain = 0;              ///< inside the domain
  std::uint64_t repairedNonPositive = 0; ///< in the domain; lambda_min <= 0 raised to the floor
  std::uint64_t repairedAnisotropy = 0;  ///< in the domain; 0 < lambda_min < floor raised
  /// Of the tensors with a value (finite, non-zero, inside the masks), as
  /// read (before the FA threshold and the repairs): lambda_min <= 0, and
  /// FA above 1 (which only a negative eigenvalue gives). Many of them mean
  /// a wrong layout (tensor_plausibility.hpp).
  std::uint64_t notPositiveDefinite = 0;
  std::uint64_t faAboveOne = 0;
  std::uint64_t repaired() const { return repairedNonPositive + repairedAnisotropy; }
  std::uint64_t withTensor() const { return total - masked - nonFinite - zero; }
};

struct MetricFromTensors {
  /// One metric tensor per voxel, in the tensors' frame; the identity
  /// outside the domain (never used there).
  std::vector<SymTensor3> metric;
  /// One byte per voxel: 1 inside the domain.
  std::vector<std::uint8_t> inDomain;
  MetricVoxelCounts counts;
};

/// The cap that applies to tensors of this kind under these options, or
/// none (a metric without --max-anisotropy).
std::optional<double> anisotropyCap(const MetricOptions& options);

/// Builds the metric and the domain from per-voxel tensors. `mask`, when
/// not empty, holds one byte per voxel (0 = outside). Throws
/// std::invalid_argument for maxAnisotropy < 1 or a mask of the wrong size.
/// `interrupter`, when given, hears start("metric"), the progress and
/// end(); when it asks to stop, Cancelled is thrown.
MetricFromTensors buildMetric(const std::vector<SymTensor3>& tensors, const std::vector<std::uint8_t>& mask,
                              const MetricOptions& options, Interrupter* interrupter = nullptr);

/// Throws NothingToCompute naming `inputName` when buildMetric left no voxel
/// in the domain; the message says whether a mask (`masked`) and an FA
/// threshold took part.
void requireNonEmptyDomain(const std::string& inputName, const MetricVoxelCounts& counts, bool masked,
                           const MetricOptions& options);

/// The fractional anisotropy of each tensor in the domain (of the tensor as
/// read, before repairs), 0 elsewhere: the values `stvd path` samples along
/// its paths.
std::vector<float> fractionalAnisotropyMap(const std::vector<SymTensor3>& tensors,
                                           const std::vector<std::uint8_t>& inDomain);

}  // namespace stvd::imaging
