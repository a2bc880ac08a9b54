// The propagation compiled once for surfaces (world tensors per vertex,
// carried into the unfolded frames by SurfaceChainUnfolding).
#include "stvd/surface/surface_propagation.hpp"

#include "stvd/propagation/propagation_definition.hpp"

namespace stvd {

template PropagationResult propagate(const SurfaceDomain&, const RiemannianMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);

}  // namespace stvd
