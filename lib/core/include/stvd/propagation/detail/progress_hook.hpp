// The progress report of a propagation's loop, paced in time rather than in
// vertices: the loop asks due() after every finalised vertex, which costs a
// bit test; every 1024 vertices it reads the clock, and only when the
// interval has passed does it build a report and call the callback and the
// interrupter (virtual and std::function calls stay out of the hot loop).
#pragma once

#include <chrono>
#include <cstdint>
#include <functional>

#include "stvd/propagation/propagation.hpp"
#include "stvd/system/interrupter.hpp"

namespace stvd::detail {

class ProgressHook {
 public:
  /// Vertices between two looks at the clock (a power of two).
  static constexpr std::uint64_t kClockEvery = 1024;

  ProgressHook(const std::function<bool(const PropagationProgress&)>& progress, Interrupter* interrupter,
               double intervalSeconds, const char* name)
      : progress_(progress),
        interrupter_(interrupter),
        interval_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(intervalSeconds))),
        next_(Clock::now() + interval_) {
    if (interrupter_) interrupter_->start(name);
  }
  ~ProgressHook() {
    if (interrupter_) interrupter_->end();
  }
  ProgressHook(const ProgressHook&) = delete;
  ProgressHook& operator=(const ProgressHook&) = delete;

  bool active() const { return interrupter_ != nullptr || static_cast<bool>(progress_); }
  /// Whether a report is due after `count` finalised vertices or points.
  bool due(std::uint64_t count) {
    if ((count & (kClockEvery - 1)) != 0 || !active()) return false;
    const Clock::time_point now = Clock::now();
    if (now < next_) return false;
    next_ = now + interval_;
    return true;
  }
  /// Reports `p`; false when the callback or the interrupter asks to stop.
  bool report(const PropagationProgress& p) {
    bool go = true;
    if (progress_) go = progress_(p);
    if (interrupter_ && interrupter_->wasInterrupted(static_cast<int>(100.0 * p.fraction))) go = false;
    return go;
  }

 private:
  using Clock = std::chrono::steady_clock;
  const std::function<bool(const PropagationProgress&)>& progress_;
  Interrupter* interrupter_;
  Clock::duration interval_;
  Clock::time_point next_;
};

}  // namespace stvd::detail
