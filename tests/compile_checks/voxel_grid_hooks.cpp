// Compiled by tests/compile_checks/CMakeLists.txt: the propagation
// instantiated for a voxel grid where the grid's propagation header (its
// DomainHooks: the candidate paths that keep STVD inside the mask) is not
// included must not compile, and the compiler must name DomainHooks. With
// STVD_WITH_HOOKS, as in the library's voxel_grid_propagation.cpp, it must.
#include <vector>

#include "stvd/propagation/propagation_definition.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"
#ifdef STVD_WITH_HOOKS
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#endif

// A norm of its own, so that the library's instantiations (extern
// templates) do not stand in for this one.
struct ScaledNorm : stvd::RiemannianNorm {};

template stvd::PropagationResult stvd::propagate(const stvd::VoxelGridDomain&, const stvd::MetricField<ScaledNorm>&,
                                                 const std::vector<stvd::VertexId>&,
                                                 const stvd::PropagationOptions&);
