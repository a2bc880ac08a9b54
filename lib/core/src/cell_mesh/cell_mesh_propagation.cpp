// The propagation compiled once for cell meshes and the built-in norms.
#include "stvd/cell_mesh/cell_mesh_propagation.hpp"

#include "stvd/propagation/propagation_definition.hpp"

namespace stvd {

template PropagationResult propagate(const CellMeshDomain&, const RiemannianMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);
template PropagationResult propagate(const CellMeshDomain&, const RandersMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);

}  // namespace stvd
