// The propagation compiled once for surfaces (world tensors per vertex,
// carried into the unfolded frames by ChainUnfolding<SurfaceDomain>).
#include "stvd/surface/surface_domain.hpp"
#include "stvd/propagation/propagation_definition.hpp"

namespace stvd {

template PropagationResult propagate(const SurfaceDomain&, const RiemannianMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);

}  // namespace stvd
