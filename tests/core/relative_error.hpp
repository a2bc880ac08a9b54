// Relative error statistics of computed distances against exact ones.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <limits>
#include <string>

namespace stvd::test {

/// Accumulates (computed - exact) / exact over a set of vertices.
class RelativeErrors {
 public:
  /// `exact` must be positive; a computed value of +inf counts as an
  /// unreached vertex (and makes the statistics fail any tolerance).
  void add(double computed, double exact) {
    ++count_;
    if (!std::isfinite(computed)) {
      ++unreached_;
      return;
    }
    const double signedError = (computed - exact) / exact;
    sum_ += std::abs(signedError);
    max_ = std::max(max_, std::abs(signedError));
    minSigned_ = std::min(minSigned_, signedError);
  }

  std::size_t count() const { return count_; }
  /// Vertices with a finite exact distance that the propagation left at +inf.
  std::size_t unreached() const { return unreached_; }
  double mean() const {
    return count_ > unreached_ ? sum_ / static_cast<double>(count_ - unreached_) : 0.0;
  }
  double max() const { return max_; }
  /// The most negative signed error: below 0 means some distance was underestimated.
  double minSigned() const { return minSigned_; }

  std::string summary() const {
    char text[160];
    std::snprintf(text, sizeof text, "mean %.5f  max %.5f  min signed %+.2e  (%zu vertices)",
                  mean(), max(), minSigned(), count());
    return text;
  }

 private:
  std::size_t count_ = 0, unreached_ = 0;
  double sum_ = 0.0, max_ = 0.0;
  double minSigned_ = std::numeric_limits<double>::infinity();
};

/// Prints a measured figure so that the test log records it next to the
/// tolerance it is checked against.
inline void reportMeasurement(const std::string& label, const RelativeErrors& e) {
  std::printf("[ measured ] %-44s %s\n", label.c_str(), e.summary().c_str());
  std::fflush(stdout);
}

}  // namespace stvd::test
