// The propagation compiled once for the built-in domains and norms.
#include "stvd/propagation_impl.hpp"

namespace stvd {

template PropagationResult propagate(const VoxelGridDomain&, const RiemannianMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);
template PropagationResult propagate(const VoxelGridDomain&, const RandersMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);
template PropagationResult propagate(const CellMeshDomain&, const RiemannianMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);
template PropagationResult propagate(const CellMeshDomain&, const RandersMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);

}  // namespace stvd
