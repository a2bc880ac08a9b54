// What a run will allocate, estimated before it starts, so that a front end
// can refuse a run that does not fit into the memory available
// (system/memory.hpp) instead of failing half-way: the propagation's and
// Lanthier's state from the sizes alone, and one run of a front end's
// PropagationChoice over each kind of domain. The one place for these
// figures; the tool and the Python package both check with them.
#pragma once

#include <cstdint>

#include "stvd/front_end/propagation_choice.hpp"

namespace stvd {

/// An upper estimate of the memory propagate() allocates over `vertexCount`
/// vertex slots of which `domainVertexCount` are in the domain (the domain
/// and the metric not included): the 16-byte record per slot, the queue
/// (allowed 64 bytes per domain vertex plus 1 MiB; on the sample brain it
/// peaked at 43 to 58 bytes per domain voxel with the 26- to 290-neighbour
/// stencils, stale entries and partly filled 4 KiB chunks included) and the
/// result's 12 bytes per slot. For checking a run against the memory
/// available before it starts (stvd/system/memory.hpp).
std::uint64_t propagationMemoryEstimate(std::uint64_t vertexCount, std::uint64_t domainVertexCount);

/// An upper estimate of the memory lanthierPropagate allocates for a graph of
/// `graphPoints` points over `vertexCount` original vertices (the cells,
/// domain and metric not included): 24 bytes per graph point (its distance,
/// queue slot and entries; 15.6 measured on the sample brain with M = 2),
/// the result's 12 bytes per vertex and 1 MiB. For checking a run against
/// the memory available before it starts.
std::uint64_t lanthierMemoryEstimate(std::uint64_t graphPoints, std::uint64_t vertexCount);

/// What one run of the choice allocates over a voxel grid of `voxels`
/// slots, `domainVoxels` of them in the domain (the grid and the metric not
/// included): propagationMemoryEstimate, or for Lanthier's method its graph
/// and the grid cells' numbering of domain voxels. For the front ends'
/// memory checks (stvd/system/memory.hpp).
std::uint64_t gridRunMemoryEstimate(const PropagationChoice& choice, std::uint64_t voxels,
                                    std::uint64_t domainVoxels);
/// The same over a surface of `vertices` vertices whose faces have
/// `corners` corners in all: the propagation, or Lanthier's graph (M points
/// on each face edge), and 64 bytes per vertex for the output.
std::uint64_t surfaceRunMemoryEstimate(const PropagationChoice& choice, std::uint64_t vertices,
                                       std::uint64_t corners);
/// The same over a tetrahedral mesh: the renumbered copies, the domain's
/// edges (built from six per tetrahedron), the propagation or Lanthier's
/// graph (at most six edges and four faces per tetrahedron carry points)
/// and the output.
std::uint64_t tetMeshRunMemoryEstimate(const PropagationChoice& choice, std::uint64_t vertices,
                                       std::uint64_t tetrahedra);

}  // namespace stvd
