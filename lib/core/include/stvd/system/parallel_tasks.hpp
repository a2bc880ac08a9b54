// Independent tasks spread over threads: the many-sources case of the
// library (one propagation per region or seed set), where every task is a
// whole propagation and the tasks share nothing but read-only input.
#pragma once

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace stvd {

/// The number of threads to use when the caller asks for `requested` (0:
/// one per core the standard library reports, at least 1) for `taskCount`
/// tasks: never more threads than tasks.
inline unsigned threadCountFor(unsigned requested, std::size_t taskCount) {
  const unsigned wanted = requested != 0 ? requested : std::max(1u, std::thread::hardware_concurrency());
  return static_cast<unsigned>(std::max<std::size_t>(1, std::min<std::size_t>(wanted, taskCount)));
}

/// Calls work(task) once for every task in 0..taskCount-1, on `threads`
/// threads (0: one per core), the calling thread among them. Tasks are
/// handed out one at a time in increasing order as threads become free, so
/// unequal tasks (a large region next to a small one) still keep every
/// thread busy. work must be safe to call concurrently for different tasks.
///
/// If a task throws, no further task is started, the running ones finish,
/// and the exception of the lowest-numbered failed task is rethrown here.
/// Which task runs on which thread varies from run to run; anything the
/// tasks write per task index is therefore the same for any thread count.
template <class Work>
void forEachTaskInParallel(std::size_t taskCount, unsigned threads, Work&& work) {
  if (taskCount == 0) return;
  const unsigned threadCount = threadCountFor(threads, taskCount);
  std::atomic<std::size_t> next{0};
  std::atomic<bool> failed{false};
  std::mutex failureMutex;
  std::exception_ptr failure;
  std::size_t failedTask = taskCount;
  auto drain = [&] {
    for (;;) {
      if (failed.load(std::memory_order_relaxed)) return;
      const std::size_t task = next.fetch_add(1, std::memory_order_relaxed);
      if (task >= taskCount) return;
      try {
        work(task);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failureMutex);
        if (task < failedTask) {
          failedTask = task;
          failure = std::current_exception();
        }
        failed.store(true, std::memory_order_relaxed);
      }
    }
  };
  std::vector<std::thread> helpers;
  helpers.reserve(threadCount - 1);
  for (unsigned t = 1; t < threadCount; ++t) helpers.emplace_back(drain);
  drain();
  for (std::thread& t : helpers) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace stvd
