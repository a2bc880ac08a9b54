// The priority queue of the propagation front: an indexed 4-ary min-heap
// with decrease-key. One 32-bit slot per vertex tells whether the vertex is
// unseen, final, or where it sits in the heap, so a vertex is in the heap at
// most once and memory stays bounded by the front size.
//
// The slots are either the queue's own array, or a field of per-vertex
// records the caller owns (every 2^strideLog2-th 32-bit word): the grid
// propagation keeps a vertex's distance, predecessor and slot in one
// 16-byte record, so that looking at a neighbour costs one cache line.
#pragma once

#include <cstdint>
#include <vector>

#include "stvd/large_array.hpp"
#include "stvd/types.hpp"

namespace stvd::detail {

class FrontQueue {
 public:
  static constexpr std::uint32_t kUnseen = 0xffffffffu;
  static constexpr std::uint32_t kFinal = 0xfffffffeu;

  /// Slots of its own for vertexCount vertices.
  explicit FrontQueue(std::size_t vertexCount)
      : ownSlots_(makeLargeArray<std::uint32_t>(vertexCount, kUnseen)),
        slots_(ownSlots_.data()),
        strideLog2_(0) {}
  /// The slot of vertex v is firstSlot[v << strideLog2], already set to
  /// kUnseen; the storage must outlive the queue.
  FrontQueue(std::uint32_t* firstSlot, unsigned strideLog2)
      : slots_(firstSlot), strideLog2_(strideLog2) {}
  FrontQueue(const FrontQueue&) = delete;
  FrontQueue& operator=(const FrontQueue&) = delete;

  bool empty() const { return heap_.empty(); }
  bool isFinal(VertexId v) const { return slot(v) == kFinal; }
  double minKey() const { return heap_.front().key; }
  VertexId minVertex() const { return heap_.front().id; }
  std::size_t capacityBytes() const {
    return heap_.capacity() * sizeof(Entry) + ownSlots_.capacity() * sizeof(std::uint32_t);
  }

  /// Inserts v with `key`, or lowers its key if it is already queued and the
  /// new key is lower. v must not be final.
  void pushOrDecrease(VertexId v, double key) {
    std::uint32_t pos = slot(v);
    if (pos == kUnseen) {
      pos = static_cast<std::uint32_t>(heap_.size());
      heap_.push_back({key, v});
    } else if (key < heap_[pos].key) {
      heap_[pos].key = key;
    } else {
      return;
    }
    siftUp(pos);
  }

  /// Removes the vertex with the smallest key and marks it final.
  VertexId popMin() {
    const VertexId top = heap_.front().id;
    slot(top) = kFinal;
    const Entry last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) siftDown(0, last);
    return top;
  }

 private:
  struct Entry {
    double key;
    VertexId id;
  };

  void siftUp(std::uint32_t pos) {
    const Entry moving = heap_[pos];
    while (pos > 0) {
      const std::uint32_t parent = (pos - 1) / 4;
      if (!(moving.key < heap_[parent].key)) break;
      heap_[pos] = heap_[parent];
      slot(heap_[pos].id) = pos;
      pos = parent;
    }
    heap_[pos] = moving;
    slot(moving.id) = pos;
  }

  // Places `moving` at the hole `pos`, moving smaller children up.
  void siftDown(std::uint32_t pos, const Entry moving) {
    const std::uint32_t n = static_cast<std::uint32_t>(heap_.size());
    for (;;) {
      const std::uint32_t first = 4 * pos + 1;
      if (first >= n) break;
      std::uint32_t best = first;
      const std::uint32_t end = first + 4 < n ? first + 4 : n;
      for (std::uint32_t c = first + 1; c < end; ++c)
        if (heap_[c].key < heap_[best].key) best = c;
      if (!(heap_[best].key < moving.key)) break;
      heap_[pos] = heap_[best];
      slot(heap_[pos].id) = pos;
      pos = best;
    }
    heap_[pos] = moving;
    slot(moving.id) = pos;
  }

  std::uint32_t& slot(VertexId v) { return slots_[static_cast<std::size_t>(v) << strideLog2_]; }
  std::uint32_t slot(VertexId v) const { return slots_[static_cast<std::size_t>(v) << strideLog2_]; }

  std::vector<Entry> heap_;
  std::vector<std::uint32_t> ownSlots_;  // empty when the caller owns the slots
  std::uint32_t* slots_;
  unsigned strideLog2_;
};

}  // namespace stvd::detail
