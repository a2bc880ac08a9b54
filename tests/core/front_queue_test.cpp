// Specification of the propagation's priority queue (detail/front_queue.hpp):
// whatever the keys, it pops vertices in exact key order, each vertex once
// with the lowest key it was given, exactly as one indexed heap would.
#include "stvd/propagation/detail/front_queue.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace stvd::detail {
namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

// The queue's contents kept the obvious way: each vertex's lowest key so far.
class ReferenceQueue {
 public:
  explicit ReferenceQueue(std::size_t n) : key_(n, kNone), final_(n, false) {}
  void push(VertexId v, double key) {
    if (std::isnan(key_[v]) || key < key_[v]) key_[v] = key;
  }
  bool empty() const {
    for (std::size_t v = 0; v < key_.size(); ++v)
      if (isQueued(static_cast<VertexId>(v))) return false;
    return true;
  }
  double minKey() const {
    double m = std::numeric_limits<double>::infinity();
    for (std::size_t v = 0; v < key_.size(); ++v)
      if (!final_[v] && !std::isnan(key_[v]) && key_[v] < m) m = key_[v];
    return m;
  }
  double keyOf(VertexId v) const { return key_[v]; }
  bool isQueued(VertexId v) const { return !final_[v] && !std::isnan(key_[v]); }
  void finish(VertexId v) { final_[v] = true; }

 private:
  std::vector<double> key_;
  std::vector<bool> final_;
};

// The queue under test next to the reference: every push goes to both, and
// every pop is checked against the reference.
class CheckedQueue {
 public:
  CheckedQueue(FrontQueue& queue, std::size_t n) : queue_(queue), reference_(n) {}

  void push(VertexId v, double key) {
    queue_.pushOrDecrease(v, key);
    reference_.push(v, key);
  }
  bool empty() { return queue_.empty(); }
  bool isFinal(VertexId v) const { return queue_.isFinal(v); }
  std::size_t pops() const { return pops_; }
  ReferenceQueue& reference() { return reference_; }

  /// Pops one vertex after empty() returned false; records a failure and
  /// returns kNoVertex if it is not a vertex with the smallest key, popped
  /// with its lowest key.
  VertexId pop() {
    const double expected = reference_.minKey();
    EXPECT_EQ(queue_.minKey(), expected);
    const VertexId v = queue_.popMin();
    EXPECT_TRUE(reference_.isQueued(v)) << "vertex " << v << " popped twice or never pushed";
    EXPECT_EQ(reference_.keyOf(v), expected) << "vertex " << v << " popped with a key not its lowest";
    EXPECT_TRUE(queue_.isFinal(v));
    if (::testing::Test::HasFailure()) return kNoVertex;
    reference_.finish(v);
    ++pops_;
    return v;
  }

  /// Pops everything left, checking each pop, until the first failure.
  void drain() {
    while (!queue_.empty())
      if (pop() == kNoVertex) return;
    EXPECT_TRUE(reference_.empty());
  }

 private:
  FrontQueue& queue_;
  ReferenceQueue reference_;
  std::size_t pops_ = 0;
};

// A Dijkstra-like run on a side x side grid graph with 8 neighbours, from
// its corner: every pop pushes the neighbours that are not final with keys a
// random "edge length" above the popped key, lowering queued keys as often
// as not, and one in eight of them, as STVD's candidates can, slightly below
// the popped key. The front sweeps across the grid, so the keys pass through
// many buckets and spreads.
void runLikeAPropagation(FrontQueue& queue, int side, double maxEdge, unsigned seed) {
  const std::size_t n = static_cast<std::size_t>(side) * side;
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> edge(0.1 * maxEdge, maxEdge);
  CheckedQueue checked(queue, n);
  checked.push(0, 0.0);
  int pushes = 0;
  while (!checked.empty()) {
    const double key = queue.minKey();
    const VertexId v = checked.pop();
    if (v == kNoVertex) return;
    const int x = static_cast<int>(v) % side, y = static_cast<int>(v) / side;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        if ((dx == 0 && dy == 0) || x + dx < 0 || x + dx >= side || y + dy < 0 || y + dy >= side)
          continue;
        const auto w = static_cast<VertexId>((y + dy) * side + x + dx);
        if (checked.isFinal(w)) continue;
        checked.push(w, ++pushes % 8 == 0 ? key - 0.01 * edge(random) : key + edge(random));
      }
  }
  EXPECT_TRUE(checked.reference().empty());
  EXPECT_EQ(checked.pops(), n);
}

TEST(FrontQueue, PopsInKeyOrderThroughAPropagationLikeRun) {
  FrontQueue queue(60 * 60);
  runLikeAPropagation(queue, 60, 1.0, 1);
}

TEST(FrontQueue, PopsInKeyOrderWhateverTheKeyScale) {
  // Buckets adapt to the key range: tiny, unit and huge edge lengths.
  for (const double maxEdge : {1e-7, 1.0, 1e6}) {
    FrontQueue queue(40 * 40);
    runLikeAPropagation(queue, 40, maxEdge, 7);
  }
}

TEST(FrontQueue, KeepsSlotsInCallerRecordsWithAStride) {
  // Four 32-bit words per vertex, the slot in the last one, as in the grid
  // propagation's records; the other words must stay untouched.
  const int side = 40;
  const std::size_t n = side * side;
  std::vector<std::uint32_t> records(4 * n, 0x5a5a5a5au);
  for (std::size_t v = 0; v < n; ++v) records[4 * v + 3] = FrontQueue::kUnseen;
  FrontQueue queue(&records[3], 2);
  runLikeAPropagation(queue, side, 2.0, 3);
  for (std::size_t v = 0; v < n; ++v)
    for (int word = 0; word < 3; ++word) ASSERT_EQ(records[4 * v + word], 0x5a5a5a5au);
}

TEST(FrontQueue, EqualKeysAndRepeatedDecreasesPopEachVertexOnce) {
  FrontQueue queue(100);
  CheckedQueue checked(queue, 100);
  for (VertexId v = 0; v < 100; ++v) checked.push(v, 5.0);
  // Lower some keys several times, raise others (ignored).
  for (VertexId v = 0; v < 100; v += 3)
    for (double key : {4.0, 6.0, 3.0, 3.5}) checked.push(v, key);
  checked.drain();
  EXPECT_EQ(checked.pops(), 100u);
}

TEST(FrontQueue, ALowerKeyJustBelowTheLastOneWins) {
  // Keys waiting for the same bucket, or the same spread, as the vertex's
  // earlier key: the lower one must be the one popped.
  FrontQueue queue(200);
  CheckedQueue checked(queue, 200);
  for (VertexId v = 0; v < 100; ++v) checked.push(v, 1.0 + v);
  for (VertexId v : {0u, 1u, 50u}) checked.push(v, std::nextafter(1.0 + v, 0.0));
  // After the first pop the rest waits in buckets; lower keys again there.
  ASSERT_FALSE(checked.empty());
  ASSERT_EQ(checked.pop(), 0u);
  for (VertexId v = 1; v < 100; v += 7)
    checked.push(v, std::nextafter(checked.reference().keyOf(v), 0.0));
  checked.drain();
  EXPECT_EQ(checked.pops(), 100u);
}

TEST(FrontQueue, FarOutlierAndInfiniteKeysComeLast) {
  FrontQueue queue(50);
  CheckedQueue checked(queue, 50);
  const double infinity = std::numeric_limits<double>::infinity();
  for (VertexId v = 0; v < 50; ++v) checked.push(v, v == 7 ? infinity : v == 9 ? 1e300 : 0.25 * v);
  checked.drain();
  EXPECT_EQ(checked.pops(), 50u);
}

TEST(FrontQueue, PushesAfterRunningEmptyStartAFreshRange) {
  FrontQueue queue(20);
  CheckedQueue checked(queue, 20);
  checked.push(0, 1.0);
  checked.drain();
  for (VertexId v = 1; v < 20; ++v) checked.push(v, 1000.0 - v);
  checked.drain();
  EXPECT_EQ(checked.pops(), 20u);
}

}  // namespace
}  // namespace stvd::detail
