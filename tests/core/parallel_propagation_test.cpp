// Many source sets propagated on several threads (stvd/system/parallel_tasks.hpp,
// stvd/propagation/source_set_propagation.hpp): every task runs exactly once, the work
// really runs concurrently, a failure surfaces on the calling thread, and
// the results do not depend on the number of threads.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <set>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "scenes.hpp"
#include "stvd/propagation/source_set_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd {
namespace {

TEST(ParallelTasks, RunsEveryTaskExactlyOnceForAnyThreadCount) {
  for (unsigned threads : {0u, 1u, 2u, 3u, 8u}) {
    for (std::size_t tasks : {std::size_t{0}, std::size_t{1}, std::size_t{2}, std::size_t{7},
                              std::size_t{100}}) {
      std::vector<std::atomic<int>> runs(tasks);
      forEachTaskInParallel(tasks, threads, [&](std::size_t t) { runs[t].fetch_add(1); });
      for (std::size_t t = 0; t < tasks; ++t)
        EXPECT_EQ(runs[t].load(), 1) << "task " << t << " of " << tasks << ", " << threads << " threads";
    }
  }
}

TEST(ParallelTasks, NeverStartsMoreThreadsThanTasks) {
  EXPECT_EQ(threadCountFor(8, 3), 3u);
  EXPECT_EQ(threadCountFor(2, 100), 2u);
  EXPECT_EQ(threadCountFor(5, 0), 1u);
  EXPECT_GE(threadCountFor(0, 100), 1u);
}

// Two tasks that can only both finish if they run at the same time: each
// waits for the other to have started (up to 120 s: a bound for a hang, not
// a time the test expects; a loaded machine may start a thread late).
TEST(ParallelTasks, TwoThreadsRunTwoTasksConcurrently) {
  std::mutex m;
  std::condition_variable cv;
  int started = 0;
  std::vector<int> sawBoth(2, 0);
  std::set<std::thread::id> threadIds;
  forEachTaskInParallel(2, 2, [&](std::size_t t) {
    std::unique_lock<std::mutex> lock(m);
    threadIds.insert(std::this_thread::get_id());
    ++started;
    cv.notify_all();
    sawBoth[t] = cv.wait_for(lock, std::chrono::seconds(120), [&] { return started == 2; }) ? 1 : 0;
  });
  EXPECT_EQ(sawBoth, (std::vector<int>{1, 1}));
  EXPECT_EQ(threadIds.size(), 2u);
}

TEST(ParallelTasks, RethrowsTheLowestFailedTaskOnTheCallingThread) {
  std::atomic<int> ran{0};
  try {
    forEachTaskInParallel(50, 2, [&](std::size_t t) {
      ran.fetch_add(1);
      if (t == 3 || t == 4) throw std::runtime_error("task " + std::to_string(t));
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    // Tasks are handed out in increasing order, so task 3 has started by the
    // time task 4 fails; the lower one is reported.
    EXPECT_STREQ(e.what(), "task 3");
  }
  // No new task starts once one has failed: at most the tasks that were
  // already handed out (two per thread at the most) ran past task 4.
  EXPECT_LE(ran.load(), 4 + 2 + 1);
}

std::vector<std::vector<VertexId>> sourceSets(const VoxelGridDomain& domain) {
  std::vector<std::vector<VertexId>> sets;
  sets.push_back({domain.vertexAt(2, 3, 4)});
  sets.push_back({domain.vertexAt(20, 5, 9), domain.vertexAt(21, 5, 9), domain.vertexAt(20, 6, 9)});
  sets.push_back({domain.vertexAt(0, 0, 0), domain.vertexAt(23, 15, 11)});
  sets.push_back({domain.vertexAt(12, 8, 6)});
  sets.push_back({domain.vertexAt(5, 14, 2)});
  return sets;
}

TEST(SourceSetPropagation, EachResultIsBitForBitTheSequentialOneWhateverTheThreadCount) {
  const VoxelGridDomain domain(test::obliqueGrid({24, 16, 12}), Stencil::full26());
  const RiemannianMetric metric(test::smoothVaryingTensors(domain));
  const auto sets = sourceSets(domain);
  for (Method method : {Method::Dijkstra, Method::ShortTermVectorDijkstra}) {
    PropagationOptions options;
    options.method = method;
    options.k = 8;
    options.chainMeasure = ChainMeasure::LargestEdgeNorm;
    std::vector<PropagationResult> sequential;
    for (const auto& set : sets) sequential.push_back(propagate(domain, metric, set, options));
    for (unsigned threads : {1u, 2u, 3u}) {
      std::vector<PropagationResult> parallel(sets.size());
      std::vector<int> calls(sets.size(), 0);
      propagateEachSourceSet(domain, metric, sets, options, threads,
                             [&](std::size_t set, PropagationResult&& r) {
                               ++calls[set];
                               parallel[set] = std::move(r);
                             });
      for (std::size_t s = 0; s < sets.size(); ++s) {
        SCOPED_TRACE("set " + std::to_string(s) + ", " + std::to_string(threads) + " threads");
        EXPECT_EQ(calls[s], 1);
        ASSERT_EQ(parallel[s].distance.size(), sequential[s].distance.size());
        EXPECT_EQ(std::memcmp(parallel[s].distance.data(), sequential[s].distance.data(),
                              sequential[s].distance.size() * sizeof(double)),
                  0);
        EXPECT_EQ(parallel[s].predecessor, sequential[s].predecessor);
        EXPECT_EQ(parallel[s].relaxedEdges, sequential[s].relaxedEdges);
      }
    }
  }
}

TEST(SourceSetPropagation, ASetWithASourceOutsideTheDomainFailsTheCall) {
  std::vector<std::uint8_t> mask(24 * 16 * 12, 1);
  const VoxelGridDomain unmasked(test::obliqueGrid({24, 16, 12}), Stencil::full26());
  mask[unmasked.vertexAt(12, 8, 6)] = 0;
  const VoxelGridDomain domain(test::obliqueGrid({24, 16, 12}), Stencil::full26(), mask);
  const RiemannianMetric metric(test::smoothVaryingTensors(domain));
  const auto sets = sourceSets(domain);  // set 3 is the masked voxel
  EXPECT_THROW(propagateEachSourceSet(domain, metric, sets, PropagationOptions{}, 2,
                                      [](std::size_t, PropagationResult&&) {}),
               std::invalid_argument);
}

}  // namespace
}  // namespace stvd
