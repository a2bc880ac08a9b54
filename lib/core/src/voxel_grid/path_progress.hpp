// How path tracing and refinement report their progress (private to the
// library): the refinement inside a tracing reports into the tracing's
// operation ("path tracing"), on its second half.
#pragma once

#include <cstdint>
#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/path_refinement.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {

/// The steps of a refinement's operation (its iterations are mapped onto
/// them; a power of two well above any maxIterations).
inline constexpr std::uint64_t kPathRefinementSteps = std::uint64_t{1} << 20;

namespace detail {

/// refineGeodesicPath reporting to `progress`, from `from` to `from + span`
/// of the scope's total as its iterations go (maxIterations).
PathRefinementReport refineGeodesicPath(const VoxelGridDomain& domain, const RiemannianMetric& metric,
                                        const std::vector<double>& distance, std::vector<Vec3d>& points,
                                        const PathRefinementOptions& options, InterruptScope& progress,
                                        std::uint64_t from, std::uint64_t span);

}  // namespace detail
}  // namespace stvd
