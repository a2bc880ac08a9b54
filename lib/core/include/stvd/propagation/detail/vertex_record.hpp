// What the propagation keeps per vertex: distance, predecessor and queue
// slot in one record of 16 bytes, or 32 with the segment measure, whose
// record also holds where its distance was measured from, a pending
// candidate until the vertex is final and its next ancestors after (its
// queue slot in the queue's own array).
// Internal to the propagation.
#pragma once

#include <cstddef>
#include <cstdint>

#include "stvd/propagation/detail/front_queue.hpp"
#include "stvd/types.hpp"

namespace stvd {
namespace detail {

/// What the propagation knows of a vertex, in one record: a neighbour's
/// distance and queue slot are read together, and with separate arrays each
/// look at a neighbour costs several cache lines. SegmentMeasure: whether
/// the run is ChainMeasure::Segment's, with its deferred measurement.
template <bool SegmentMeasure>
struct VertexRecord;

/// Dijkstra and the chain rules: 16 bytes.
template <>
struct VertexRecord<false> {
  double distance;  // the key in the queue; the distance once final
  VertexId predecessor;
  std::uint32_t queueSlot;  // FrontQueue's slot

  static VertexRecord unseen() { return {kUnreachable, kNoVertex, FrontQueue::kUnseen}; }
  double key() const { return distance; }
  double finalDistance() const { return distance; }
};

/// ChainMeasure::Segment with deferred measurement (see
/// Propagation::settleMin): 32 bytes, and the queue slot in the front
/// queue's own array.
///
/// Two predecessors: `predecessor` links the chain of edges that the
/// k-vertex memory walks: once the vertex is final, the neighbour whose
/// measured candidate (or Dijkstra term) gave its distance, as `link` kept
/// it while the vertex was open (while a candidate is pending, the
/// neighbour whose relaxation gave the key and the pending candidate).
/// `base` is the vertex the distance was measured from, the start of the
/// straight segment that gave it (the neighbour itself for the Dijkstra
/// term), which links the any-angle ancestors and is the result's
/// predecessor. Linking the chain through the neighbour whose screened
/// candidate last lowered the key instead widened the brain's band against
/// Lanthier (docs/accuracy.md).
///
/// Keeping both and the pending candidate takes 36 bytes with the queue
/// slot; the slot, read for every neighbour a relaxation looks at, moved to
/// the queue's own array (4 bytes per vertex, prefetched with the
/// neighbours' records) rather than the record growing to 64 bytes, which
/// measured no faster (docs/accuracy.md, "The chain linked as on main").
///
/// The key, `link` and the pending candidate matter only until the vertex
/// is final; from then on the same bytes hold its next ancestors along the
/// chain of edges (pred(pred(v)) onwards). A relaxation then reads the whole
/// chain of k <= 3 + kStoredAncestors vertices from v's record and its
/// predecessor's, instead of walking it record by record: a walk of
/// dependent loads into voxels finalised long ago, each a likely cache miss
/// that the next could not overlap.
template <>
struct VertexRecord<true> {
  static constexpr int kStoredAncestors = 4;
  /// What a vertex not yet final carries.
  struct Open {
    double key;            // the key in the queue: a pending candidate's screen, or `measured`
    VertexId pendingBase;  // c_{i-1} of the pending candidate; kNoVertex for none
    VertexId link;         // the neighbour whose relaxation or pending candidate gave `measured`
  };

  double measured;           // shortest measured distance: the distance once final
  VertexId predecessor;      // see above: the chain of edges' link
  VertexId base;             // where `measured` was measured from
  union {
    Open open;                             // until the vertex is final
    VertexId ancestors[kStoredAncestors];  // once it is relaxed: c_2, c_3, ... of its chain
  };

  static VertexRecord unseen() {
    VertexRecord r;
    r.measured = kUnreachable;
    r.predecessor = kNoVertex;
    r.base = kNoVertex;
    r.open = Open{kUnreachable, kNoVertex, kNoVertex};
    return r;
  }
  double finalDistance() const { return measured; }
};

}  // namespace detail
}  // namespace stvd
