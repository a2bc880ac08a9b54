// One interface through which every long operation reports its progress and
// can be stopped: a progress bar, a GUI's cancel button and a host's
// pipeline (ITK's ProgressEvent and AbortGenerateData) all plug in here.
// OpenVDB's util::NullInterrupter is the model: start(name), end(),
// wasInterrupted(percent).
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace stvd {

/// Receives the progress of long operations and may stop them. The default
/// implementation does nothing and never interrupts; derive and override
/// what you need.
///
/// An operation calls start() once when it begins and end() once when it
/// ends (also when it was interrupted or failed), and wasInterrupted() at
/// its start (0 %), at least about every kDefaultInterruptInterval seconds
/// of its work, and at its end (100 %, unless it was interrupted). The
/// calls come from the thread that runs the operation; with
/// propagateEachSourceSet they come from several threads at once.
class Interrupter {
 public:
  virtual ~Interrupter() = default;
  /// `name` says what begins: "propagation", "Steiner-point propagation",
  /// "metric".
  virtual void start(const char* name) { (void)name; }
  virtual void end() {}
  /// `percent` in [0, 100], or -1 when unknown. Return true to stop the
  /// operation: a propagation then ends with Termination::Cancelled and no
  /// distances, another operation throws Cancelled.
  virtual bool wasInterrupted(int percent = -1) {
    (void)percent;
    return false;
  }
};

/// The longest time between two reports of a running operation, seconds: a
/// cancel takes effect within about this long.
inline constexpr double kDefaultInterruptInterval = 0.05;

/// Thrown by an operation that was interrupted and has no partial result to
/// return (building a metric). Not an stvd::Error: nothing was wrong with
/// the input.
class Cancelled : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// An Interrupter driven through a loop of `total` steps: start(name) at
/// construction with a report of 0 %, end() at destruction; step(done)
/// after each step costs a bit test, looks at the clock every 1024 steps
/// and reports when the interval has passed; check(done) after a coarse
/// step (a piece of an array filled, a whole path) looks at the clock every
/// time; finish() reports 100 %. Throws Cancelled ("<name> was
/// interrupted") when the interrupter asks to stop. Does nothing without an
/// interrupter.
class InterruptScope {
 public:
  InterruptScope(Interrupter* interrupter, const char* name, std::uint64_t total,
                 double intervalSeconds = kDefaultInterruptInterval)
      : interrupter_(interrupter),
        name_(name),
        total_(total),
        interval_(std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(intervalSeconds))),
        next_(Clock::now() + interval_) {
    if (!interrupter_) return;
    interrupter_->start(name_);
    try {
      ask(0);
    } catch (...) {  // no destructor runs for an object whose constructor throws
      interrupter_->end();
      throw;
    }
  }
  ~InterruptScope() {
    if (interrupter_) interrupter_->end();
  }
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

  void step(std::uint64_t done) {
    if ((done & 1023) == 0) check(done);
  }
  void check(std::uint64_t done) {
    if (!interrupter_) return;
    const Clock::time_point now = Clock::now();
    if (now < next_) return;
    next_ = now + interval_;
    ask(total_ > 0 ? static_cast<int>(100 * std::min(done, total_) / total_) : -1);
  }
  /// The total once it is known better; a smaller one than before keeps
  /// the percents non-decreasing.
  void setTotal(std::uint64_t total) { total_ = total; }
  void finish() {
    if (interrupter_) ask(100);
  }

 private:
  using Clock = std::chrono::steady_clock;
  void ask(int percent) {
    if (interrupter_->wasInterrupted(percent)) throw Cancelled(std::string(name_) + " was interrupted");
  }
  Interrupter* interrupter_;
  const char* name_;
  std::uint64_t total_;
  Clock::duration interval_;
  Clock::time_point next_;
};

}  // namespace stvd
