// The propagation compiled once for voxel grids and the built-in norms.
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

#include "stvd/propagation/propagation_definition.hpp"

namespace stvd {

std::uint64_t propagationMemoryEstimate(std::uint64_t vertexCount, std::uint64_t domainVertexCount) {
  constexpr std::uint64_t kRecord = 16, kResult = sizeof(double) + sizeof(VertexId), kQueuePerVertex = 64;
  return (kRecord + kResult) * vertexCount + kQueuePerVertex * domainVertexCount + (std::uint64_t{1} << 20);
}

template PropagationResult propagate(const VoxelGridDomain&, const RiemannianMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);
template PropagationResult propagate(const VoxelGridDomain&, const RandersMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);

}  // namespace stvd
