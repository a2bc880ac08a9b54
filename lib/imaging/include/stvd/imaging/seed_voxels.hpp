// Seeds (and path targets) as a front end's user gives them, turned into
// voxels of a tensor volume's domain: voxel indices, physical points and the
// non-zero voxels of a label image, with the messages that say why one
// cannot be used.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "stvd/imaging/scalar_image.hpp"
#include "stvd/imaging/tensor_input.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd::imaging {

/// A voxel the user named, and how (for messages).
struct SeedVoxel {
  VoxelIndex index;
  std::string givenAs;
};

/// "(i, j, k)".
std::string voxelText(const VoxelIndex& v);
/// "(x, y, z)" with `decimals` digits.
std::string pointText(const Vec3d& p, int decimals);
/// The point with x and y negated: LPS <-> RAS (its own inverse).
Vec3d lpsToRas(const Vec3d& p);

/// Why voxel v (linear index) of `input` is outside the domain that
/// buildMetric made with `metric`, e.g. "its tensor is zero (no data there)".
std::string whyOutsideDomain(std::size_t v, const TensorInput& input, const MetricOptions& metric);

/// The voxels given as indices and as physical points (RAS millimetres, or
/// LPS when pointsInLps; the nearest voxel), in that order. Each must lie
/// in the image and in the domain (`inDomain`, from buildMetric); otherwise
/// NothingToCompute names `inputName`, the `role` ("seed" or "target") and
/// the reason.
std::vector<SeedVoxel> seedVoxelsAt(const std::string& inputName, const std::vector<std::array<int, 3>>& voxels,
                                    const std::vector<std::array<double, 3>>& points, bool pointsInLps,
                                    const TensorInput& input, const MetricOptions& metric,
                                    const std::vector<std::uint8_t>& inDomain, const std::string& role = "seed");

/// The non-zero (and not NaN) voxels of `labels` that lie in the domain;
/// the others are left out and counted in `leftOut`. Throws ImageIoError
/// when the labels are on another grid than `geometry` (the tensors'), and
/// NothingToCompute when no label voxel is non-zero or none lies in the
/// domain. `labelsName` and `inputName` name the two in messages.
std::vector<SeedVoxel> labelSeedVoxels(const std::string& labelsName, const ScalarImage& labels,
                                       const std::string& inputName, const GridGeometry& geometry,
                                       const std::vector<std::uint8_t>& inDomain, std::size_t& leftOut);

/// The end of a path: a vertex of the domain and how the user named it.
struct PathTarget {
  VertexId vertex = kNoVertex;
  std::string name;
};

/// One target per distinct non-zero label of `labels` (labelRegions): the
/// region's voxel in the domain with the smallest distance from the seeds
/// (the end of the shortest path from the seeds to the region). Throws
/// ImageIoError when the labels are on another grid than `geometry`,
/// NothingToCompute when no voxel is non-zero or a label has no reached
/// voxel in the domain.
std::vector<PathTarget> labelTargets(const std::string& labelsName, const LabelImage& labels,
                                     const std::string& inputName, const GridGeometry& geometry,
                                     const std::vector<std::uint8_t>& inDomain, const std::vector<double>& distance);

/// Throws NothingToCompute naming `inputName` and the first target that
/// has no finite distance (no path inside the domain reaches it).
void requireReachable(const std::string& inputName, const std::vector<PathTarget>& targets,
                      const std::vector<double>& distance);

/// The vertices of the seeds, sorted, each once: the sources of a
/// propagation.
std::vector<VertexId> sourceVertices(const VoxelGridDomain& domain, const std::vector<SeedVoxel>& seeds);

}  // namespace stvd::imaging
