// What the propagation keeps per vertex: distance, predecessor and queue
// slot in one record of 16 bytes, or 32 with the segment measure, whose
// record also holds where its distance was measured from, a pending
// candidate until the vertex is final and its next ancestors after.
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
/// Propagation::settleMin): 32 bytes.
///
/// Two predecessors: `predecessor`, the neighbour whose relaxation gave the
/// vertex its key, links the chain of edges that the k-vertex memory walks;
/// `base` is the vertex the distance was measured from, the start of the
/// straight segment that gave it (the neighbour itself for the Dijkstra
/// term), which links the any-angle ancestors and is the result's
/// predecessor.
///
/// The key and the pending candidate matter only until the vertex is final;
/// from then on the same bytes hold its next ancestors along the chain of
/// edges (pred(pred(v)) onwards). A relaxation then reads the whole chain of
/// k <= 3 + kStoredAncestors vertices from v's record and its
/// predecessor's, instead of walking it record by record: a walk of
/// dependent loads into voxels finalised long ago, each a likely cache miss
/// that the next could not overlap.
template <>
struct VertexRecord<true> {
  static constexpr int kStoredAncestors = 3;
  /// What a vertex not yet final carries.
  struct Open {
    double key;            // the key in the queue: a pending candidate's screen, or `measured`
    VertexId pendingBase;  // c_{i-1} of the pending candidate; kNoVertex for none
    VertexId base;         // where `measured` was measured from
  };
  /// What it carries once final (`base` stays where it was).
  struct Final {
    VertexId ancestors[kStoredAncestors];  // once it is relaxed: c_2, c_3, c_4 of its chain
    VertexId base;                         // where its distance was measured from
  };

  double measured;           // shortest measured distance: the distance once final
  std::uint32_t queueSlot;   // FrontQueue's slot
  VertexId predecessor;      // the vertex whose relaxation gave the key
  union {
    Open open;    // until the vertex is final
    Final done;   // once it is final; done.base is open.base (same type, same place)
  };

  static VertexRecord unseen() {
    VertexRecord r;
    r.measured = kUnreachable;
    r.queueSlot = FrontQueue::kUnseen;
    r.predecessor = kNoVertex;
    r.open = Open{kUnreachable, kNoVertex, kNoVertex};
    return r;
  }
  double finalDistance() const { return measured; }
};
static_assert(offsetof(VertexRecord<true>::Open, base) == offsetof(VertexRecord<true>::Final, base),
              "a final vertex's base is where it was while it was open");

}  // namespace detail
}  // namespace stvd
