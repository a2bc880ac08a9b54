// An Interrupter that records what long operations report to it, and the
// protocol every one of them follows (system/interrupter.hpp): start(name),
// 0 % first, non-decreasing percents, 100 % last unless it was stopped,
// end(). It can stop an operation at its first report after the start.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <mutex>
#include <string>
#include <vector>

#include "stvd/system/interrupter.hpp"

namespace stvd::testing {

class InterruptRecorder : public Interrupter {
 public:
  struct Operation {
    std::string name;
    std::vector<int> percents;
    bool ended = false;
  };

  /// Stops the operation named `name` (every one when empty) at its first
  /// report after the one at its start.
  void stopAtFirstReportAfterStart(std::string name = {}) {
    stopping_ = true;
    stopAtReport_ = 2;
    stopName_ = std::move(name);
  }
  /// Stops it at its first report (0 %, at its start).
  void stopAtStart(std::string name = {}) {
    stopping_ = true;
    stopAtReport_ = 1;
    stopName_ = std::move(name);
  }

  void start(const char* name) override {
    std::lock_guard<std::mutex> lock(mutex_);
    open_.push_back(operations_.size());
    operations_.push_back({name, {}, false});
  }
  void end() override {
    std::lock_guard<std::mutex> lock(mutex_);
    ASSERT_FALSE(open_.empty()) << "end() without start()";
    operations_[open_.back()].ended = true;
    open_.pop_back();
  }
  bool wasInterrupted(int percent) override {
    std::lock_guard<std::mutex> lock(mutex_);
    EXPECT_FALSE(open_.empty()) << "a report outside start() .. end()";
    if (open_.empty()) return false;
    Operation& o = operations_[open_.back()];
    o.percents.push_back(percent);
    if (stopped_) ++reportsAfterStop_;
    const bool stop = stopping_ && o.percents.size() >= stopAtReport_ && (stopName_.empty() || o.name == stopName_);
    stopped_ = stopped_ || stop;
    return stop;
  }

  const std::vector<Operation>& operations() const { return operations_; }
  /// The operations of that name, in the order they started.
  std::vector<Operation> named(const std::string& name) const {
    std::vector<Operation> found;
    for (const Operation& o : operations_)
      if (o.name == name) found.push_back(o);
    return found;
  }
  bool stopped() const { return stopped_; }
  /// Reports heard after the one that stopped (from the stopped operation
  /// or any other: nothing should go on).
  std::size_t reportsAfterStop() const { return reportsAfterStop_; }
  bool allEnded() const { return open_.empty(); }

 private:
  std::mutex mutex_;
  std::vector<Operation> operations_;
  std::vector<std::size_t> open_;  // started and not ended, innermost last
  bool stopping_ = false;
  std::size_t stopAtReport_ = 2;
  std::string stopName_;
  bool stopped_ = false;
  std::size_t reportsAfterStop_ = 0;
};

/// An operation that ran to its end: 0 % first, 100 % last, percents that
/// never decrease (-1, unknown, is not expected), ended.
inline void expectCompleteReports(const InterruptRecorder::Operation& o) {
  SCOPED_TRACE("operation \"" + o.name + "\"");
  ASSERT_GE(o.percents.size(), 2u);
  EXPECT_EQ(o.percents.front(), 0);
  EXPECT_EQ(o.percents.back(), 100);
  for (std::size_t i = 1; i < o.percents.size(); ++i)
    EXPECT_LE(o.percents[i - 1], o.percents[i]) << "report " << i;
  EXPECT_TRUE(o.ended);
}

}  // namespace stvd::testing
