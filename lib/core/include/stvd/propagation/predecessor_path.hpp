// The path of the propagation itself: a vertex's predecessor chain back to
// its source, on any domain. (A continuous path traced down the distance
// field is the grid's: voxel_grid/path_tracing.hpp.)
#pragma once

#include <vector>

#include "stvd/propagation/propagation.hpp"
#include "stvd/types.hpp"

namespace stvd {

namespace detail {
/// What predecessorPath and the path tracing say to a result that keeps no
/// predecessors.
inline constexpr char kNoPredecessorsMessage[] =
    "the propagation result keeps no predecessors (a Steiner-point propagation tracks none): "
    "trace paths from a Dijkstra or STVD result";
}  // namespace detail

/// The predecessor chain of `target`, from its source (first) to `target`
/// (last). Empty when the target has no finite distance. Throws
/// std::invalid_argument when `target` is out of range or the result keeps
/// no predecessors (a Steiner-point propagation), and std::logic_error
/// when the chain does not end at a vertex of distance 0 within vertexCount
/// steps (a corrupt predecessor array).
std::vector<VertexId> predecessorPath(const PropagationResult& result, VertexId target);

}  // namespace stvd
