// The priority queue of the propagation front, in two levels: an indexed
// 4-ary min-heap with decrease-key holds only the keys of the current narrow
// key bucket ("hot"), and every later key waits unsorted in a flat bucket
// list ("cold") until its bucket becomes current. Pops come out in exact key
// order, as from one heap.
//
// Why two levels: a single heap holds the whole front, several MiB at 256^3.
// Each sift step then moves an entry and writes the queue slot of a vertex
// anywhere on the front, so a pop or a decrease-key is a chain of dependent
// cache misses whose length grows with the volume. Appending to a bucket
// touches one line, and the hot heap (about 1/256 of the front) and the
// records of its vertices stay in cache.
//
// One 32-bit slot per vertex tells whether the vertex is unseen, final,
// cold, or where it sits in the heap. The slots are either the queue's own
// array, or a field of per-vertex records the caller owns (every
// 2^strideLog2-th 32-bit word): the grid propagation keeps a vertex's
// distance, predecessor and slot in one 16-byte record, so that looking at a
// neighbour costs one cache line.
//
// Buckets. A key's place is t = (key - base) / width: t below the current
// bucket's end goes into the heap, t below kBucketCount into bucket floor(t),
// anything further into the overflow list. Because t is a monotone function
// of the key, every key in a bucket is at most every key in the buckets and
// the overflow after it. When the heap runs empty the next non-empty bucket
// is moved into it; when every bucket is used up, the overflow is spread
// over a fresh set of buckets starting at its smallest key, with a width
// that makes the buckets span four times the overflow's key range (about the
// range of keys on the front, so that the buckets last while the front
// advances by several such ranges). The bucket lists share one pool of 4 KiB
// chunks (chunked_lists.hpp), so that memory follows the entries queued.
//
// A cold vertex whose key drops is appended again, as the queue does not know
// where its earlier entry is; the lowest of its entries is moved into the
// heap first, and the others are recognised as stale by the vertex's slot
// (in the heap or final) and dropped when their bucket is reached.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "stvd/detail/compiler.hpp"
#include "stvd/propagation/detail/chunked_lists.hpp"
#include "stvd/system/large_array.hpp"
#include "stvd/types.hpp"

namespace stvd::detail {

class FrontQueue {
 public:
  static constexpr std::uint32_t kUnseen = 0xffffffffu;
  static constexpr std::uint32_t kFinal = 0xfffffffeu;
  static constexpr std::uint32_t kCold = 0xfffffffdu;
  /// Heap positions lie below this value.
  static constexpr std::uint32_t kMaxHeapSize = kCold;
  static constexpr int kBucketCount = 1024;

  /// Slots of its own for vertexCount vertices.
  explicit FrontQueue(std::size_t vertexCount)
      : ownSlots_(makeLargeArray<std::uint32_t>(vertexCount, kUnseen)),
        slots_(ownSlots_.data()),
        strideLog2_(0),
        cold_(kBucketCount + 1) {}
  /// The slot of vertex v is firstSlot[v << strideLog2], already set to
  /// kUnseen; the storage must outlive the queue.
  FrontQueue(std::uint32_t* firstSlot, unsigned strideLog2)
      : slots_(firstSlot), strideLog2_(strideLog2), cold_(kBucketCount + 1) {}
  FrontQueue(const FrontQueue&) = delete;
  FrontQueue& operator=(const FrontQueue&) = delete;

  /// True when no vertex is queued. Moves the next cold bucket into the heap
  /// when the heap has run empty, so that minKey() and minVertex() can be
  /// called after it returned false.
  bool empty() {
    if (heap_.empty() && coldEntries_ != 0) refill();
    return heap_.empty();
  }
  bool isFinal(VertexId v) const { return slot(v) == kFinal; }
  /// Where vertex v's slot lies (to prefetch it).
  const std::uint32_t* slotAddress(VertexId v) const { return &slots_[static_cast<std::size_t>(v) << strideLog2_]; }
  /// The smallest queued key and its vertex; only after empty() returned false.
  double minKey() const { return heap_.front().key; }
  VertexId minVertex() const { return heap_.front().id; }
  std::size_t capacityBytes() const {
    return heap_.capacity() * sizeof(Entry) + cold_.capacityBytes() +
           ownSlots_.capacity() * sizeof(std::uint32_t);
  }

  /// Queues v with `key`, or lowers its key if it is already queued and the
  /// new key is lower. v must not be final.
  STVD_ALWAYS_INLINE void pushOrDecrease(VertexId v, double key) {
    const std::uint32_t pos = slot(v);
    if (pos < kMaxHeapSize) {
      if (key < heap_[pos].key) {
        heap_[pos].key = key;
        siftUp(pos);
      }
      return;
    }
    place({key, v});
  }

  /// Gives the vertex with the smallest key the larger key `key` and queues
  /// it again where that key belongs (the heap, a bucket or the overflow);
  /// only after empty() returned false. The propagation uses it when a
  /// vertex's key was an estimate that turned out too low once measured.
  /// A key raised into a later bucket leaves the vertex's earlier, lower
  /// entries in the buckets valid in the queue's eyes (it knows a vertex's
  /// entries only by its slot): the caller recognises one when it reaches
  /// the top with a key below the vertex's own, and requeues it.
  void requeueMin(double key) {
    const VertexId top = heap_.front().id;
    if ((key - base_) * inverseWidth_ < hotEnd_) {
      // Still in the current bucket: one sift down from the root, which
      // stops at once when the vertex is still the smallest.
      siftDown(0, {key, top});
      return;
    }
    const Entry last = heap_.back();
    heap_.pop_back();
    if (!heap_.empty()) siftDown(0, last);
    slot(top) = kUnseen;
    place({key, top});
  }

  /// Removes a vertex with the smallest key and marks it final; only after
  /// empty() returned false.
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

  // Puts an unseen or cold vertex into the heap, a bucket or the overflow.
  STVD_ALWAYS_INLINE void place(const Entry& e) {
    const double t = (e.key - base_) * inverseWidth_;
    if (t < hotEnd_) {
      const auto pos = static_cast<std::uint32_t>(heap_.size());
      heap_.push_back(e);
      siftUp(pos);
      return;
    }
    slot(e.id) = kCold;
    ++coldEntries_;
    cold_.append(t < bucketEnd_ ? static_cast<std::size_t>(t) : kOverflow, e);
  }

  // Called with an empty heap and cold entries: moves the next bucket with a
  // live entry into the heap, spreading the overflow when the buckets are
  // used up.
  void refill() {
    while (heap_.empty() && coldEntries_ != 0) {
      while (++current_ < kBucketCount && cold_.empty(current_)) {
      }
      if (current_ < kBucketCount) {
        hotEnd_ = static_cast<double>(current_ + 1);
        promote(current_);
      } else {
        spreadOverflow();
      }
    }
  }

  // Moves the live entries of a bucket into the heap and empties it. The
  // slots lie anywhere on the front and are asked for a few entries ahead.
  void promote(int bucket) {
    constexpr int kAhead = 16;
    cold_.drain(static_cast<std::size_t>(bucket), [this](const Entry* run, int n) {
      for (int i = 0; i < kAhead && i < n; ++i) prefetch(&slot(run[i].id));
      for (int i = 0; i < n; ++i) {
        if (i + kAhead < n) prefetch(&slot(run[i + kAhead].id));
        mergeIntoHeap(run[i]);
      }
      coldEntries_ -= static_cast<std::size_t>(n);
    });
  }

  // A cold entry reaches the heap: the vertex enters it, or its key is
  // lowered if an earlier entry brought it there; a final vertex's entry is
  // dropped.
  STVD_ALWAYS_INLINE void mergeIntoHeap(const Entry& e) {
    const std::uint32_t pos = slot(e.id);
    if (pos == kCold) {
      const auto last = static_cast<std::uint32_t>(heap_.size());
      heap_.push_back(e);
      siftUp(last);
    } else if (pos < kMaxHeapSize && e.key < heap_[pos].key) {
      heap_[pos].key = e.key;
      siftUp(pos);
    }
  }

  // All buckets are used up and the heap is empty: spreads the overflow
  // over new buckets that start at its smallest key. Entries of final
  // vertices take part in choosing the width (reading their slots for that
  // would be a cache miss each) but are dropped.
  void spreadOverflow() {
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    cold_.forEachRun(kOverflow, [&](const Entry* run, int n) {
      for (int i = 0; i < n; ++i) {
        lo = std::min(lo, run[i].key);
        hi = std::max(hi, run[i].key);
      }
    });
    // Four key ranges across all buckets. A zero range (all keys equal, as
    // for the sources) keeps the last width, or takes a tiny one at the
    // start; the keys that follow then set a proper width at the next spread.
    double width = 4.0 * (hi - lo) / kBucketCount;
    if (!(width > 0.0)) width = width_ > 0.0 ? width_ : std::max(std::abs(lo), 1.0) * 1e-9;
    const bool finite = std::isfinite(lo) && std::isfinite(width);
    if (finite) {
      width_ = width;
      base_ = lo;
      inverseWidth_ = 1.0 / width;
      hotEnd_ = 1.0;
      bucketEnd_ = kBucketCount;
      current_ = 0;
    } else {
      // Infinite keys (or a range beyond the doubles) fit no bucket: they
      // all go into the heap, and so does every key after them until the
      // heap runs empty again.
      base_ = 0.0;
      inverseWidth_ = 0.0;
      hotEnd_ = std::numeric_limits<double>::infinity();
      bucketEnd_ = hotEnd_;
      current_ = kBucketCount;
    }
    cold_.drain(kOverflow, [&](const Entry* run, int n) {
      coldEntries_ -= static_cast<std::size_t>(n);
      for (int i = 0; i < n; ++i) {
        // A vertex may have several entries here; once one of them is in
        // the heap, the others only lower its key there.
        const std::uint32_t pos = slot(run[i].id);
        if (pos == kFinal) continue;
        if (pos == kCold && finite)
          place(run[i]);
        else
          mergeIntoHeap(run[i]);
      }
    });
  }

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

  // The buckets. Until the first spread every key goes to the overflow
  // (t = 0 is below neither hotEnd_ nor bucketEnd_).
  static constexpr std::size_t kOverflow = kBucketCount;  // the list after the buckets
  ChunkedLists<Entry, 255> cold_;  // 4 KiB chunks
  std::size_t coldEntries_ = 0;   // entries in buckets and overflow, stale ones included
  double base_ = 0.0;
  double inverseWidth_ = 0.0;
  double width_ = 0.0;
  double hotEnd_ = 0.0;     // t below it: the heap
  double bucketEnd_ = 0.0;  // t below it: a bucket; kBucketCount after a spread
  int current_ = kBucketCount;  // the bucket last moved into the heap
};

}  // namespace stvd::detail
