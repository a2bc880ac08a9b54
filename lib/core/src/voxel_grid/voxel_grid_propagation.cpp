// The propagation compiled once for voxel grids and the built-in norms.
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

#include "stvd/propagation/propagation_definition.hpp"

namespace stvd {

template PropagationResult propagate(const VoxelGridDomain&, const RiemannianMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);
template PropagationResult propagate(const VoxelGridDomain&, const RandersMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);

}  // namespace stvd
