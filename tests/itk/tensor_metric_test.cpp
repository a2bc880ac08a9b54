// The metric built from diffusion tensors, the repairs of ill-conditioned
// tensors and the domain they leave.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "stvd/imaging/symmetric_eigen.hpp"
#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "test_support.hpp"

namespace stvd::imaging {
namespace {

using stvd::testing::relativeDifference;
using stvd::testing::rotation;

SymTensor3 diagonal(double a, double b, double c) {
  return {static_cast<float>(a), 0.f, 0.f, static_cast<float>(b), 0.f, static_cast<float>(c)};
}

MetricFromTensors build(const std::vector<SymTensor3>& tensors, MetricOptions options = {}) {
  return buildMetric(tensors, {}, options);
}

TEST(DiffusionMetric, IsotropicTissueCostsOnePerMillimetreWhateverItsDiffusivity) {
  for (double d : {3e-3, 7e-4, 1e-6, 2.5}) {
    const MetricFromTensors m = build({diagonal(d, d, d)});
    EXPECT_LT(relativeDifference(m.metric[0], diagonal(1, 1, 1)), 1e-6) << "D = " << d << " I";
  }
}

TEST(DiffusionMetric, NormalisedInverseHasEigenvaluesMdOverLambda) {
  // lambda = (1.5, 0.5, 0.25) e-3, MD = 0.75e-3: G = diag(0.5, 1.5, 3).
  const MetricFromTensors m = build({diagonal(1.5e-3, 0.5e-3, 0.25e-3)});
  EXPECT_LT(relativeDifference(m.metric[0], diagonal(0.5, 1.5, 3.0)), 1e-6);
}

TEST(DiffusionMetric, NormalisedAdjugateIsTheInverseTimesTheDeterminantOfDOverMd) {
  // D/MD = diag(2, 2/3, 1/3), det = 4/9; adj = diag(2/9, 2/3, 4/3).
  MetricOptions options;
  options.diffusionMetric = DiffusionMetric::NormalizedAdjugate;
  const MetricFromTensors m = build({diagonal(1.5e-3, 0.5e-3, 0.25e-3)}, options);
  EXPECT_LT(relativeDifference(m.metric[0], diagonal(2.0 / 9, 2.0 / 3, 4.0 / 3)), 1e-6);
}

TEST(DiffusionMetric, FollowsTheTensorsOrientation) {
  // The same tensor rotated gives the same metric rotated.
  const Matrix3 r = rotation(1, -1, 2, 35);
  const MetricFromTensors rotated = build({changeTensorFrame(diagonal(1.5e-3, 0.5e-3, 0.25e-3), r)});
  EXPECT_LT(relativeDifference(rotated.metric[0], changeTensorFrame(diagonal(0.5, 1.5, 3.0), r)), 1e-5);
}

TEST(MetricKind, TakesTheTensorAsTheMetric) {
  MetricOptions options;
  options.kind = TensorKind::Metric;
  const SymTensor3 g{2.f, 0.3f, -0.2f, 1.f, 0.1f, 0.5f};
  const MetricFromTensors m = build({g}, options);
  EXPECT_LT(relativeDifference(m.metric[0], g), 1e-6);
  EXPECT_EQ(m.counts.repaired(), 0u);
}

TEST(MetricKind, IsTakenAsGivenWithoutACap) {
  // An anisotropy of 400 (eigenvalue ratio): a diffusion tensor would be
  // capped at 100 by default, a metric is not, and nothing is counted as
  // repaired.
  MetricOptions options;
  options.kind = TensorKind::Metric;
  const SymTensor3 g = diagonal(4, 1, 0.01);
  const MetricFromTensors m = build({g}, options);
  EXPECT_LT(relativeDifference(m.metric[0], g), 1e-6);
  EXPECT_EQ(m.counts.repaired(), 0u);
  EXPECT_FALSE(anisotropyCap(options).has_value());
  options.kind = TensorKind::Diffusion;
  EXPECT_EQ(anisotropyCap(options), kDefaultMaxAnisotropy);
}

TEST(MetricKind, WithoutACapOnlyNonPositiveEigenvaluesAreRaised) {
  MetricOptions options;
  options.kind = TensorKind::Metric;
  const MetricFromTensors m = build({diagonal(2, -1, 0.001), diagonal(2, 0.001, 1)}, options);
  EXPECT_LT(relativeDifference(m.metric[0], diagonal(2, 0.02, 0.001)), 1e-5);
  EXPECT_LT(relativeDifference(m.metric[1], diagonal(2, 0.001, 1)), 1e-6);
  EXPECT_EQ(m.counts.repairedNonPositive, 1u);
  EXPECT_EQ(m.counts.repairedAnisotropy, 0u);
}

TEST(Repairs, RaiseSmallEigenvaluesToTheAnisotropyFloor) {
  MetricOptions options;
  options.kind = TensorKind::Metric;
  options.maxAnisotropy = 10.0;
  const MetricFromTensors m = build({diagonal(5, 1, 0.01)}, options);
  EXPECT_LT(relativeDifference(m.metric[0], diagonal(5, 1, 0.5)), 1e-6);
  EXPECT_EQ(m.counts.repairedAnisotropy, 1u);
  EXPECT_EQ(m.counts.repairedNonPositive, 0u);
  EXPECT_EQ(m.counts.domain, 1u);
}

TEST(Repairs, RaiseZeroAndNegativeEigenvaluesAndCountThemApart) {
  MetricOptions options;
  options.kind = TensorKind::Metric;
  options.maxAnisotropy = 100.0;
  const MetricFromTensors m = build({diagonal(2, -1, 0.5), diagonal(2, 0, 1), diagonal(2, 1, 1)}, options);
  EXPECT_LT(relativeDifference(m.metric[0], diagonal(2, 0.02, 0.5)), 1e-6);
  EXPECT_LT(relativeDifference(m.metric[1], diagonal(2, 0.02, 1)), 1e-6);
  EXPECT_EQ(m.counts.repairedNonPositive, 2u);
  EXPECT_EQ(m.counts.repairedAnisotropy, 0u);
  EXPECT_EQ(m.counts.repaired(), 2u);
  EXPECT_EQ(m.counts.domain, 3u);
}

TEST(Repairs, LeaveTheConditionNumberAtMostTheCap) {
  const double cap = 25.0;
  MetricOptions options;
  options.maxAnisotropy = cap;
  const MetricFromTensors m = build({changeTensorFrame(diagonal(2e-3, 1e-9, -3e-4), rotation(3, 1, 2, 50))}, options);
  const SymmetricEigen e = eigenDecompose(m.metric[0]);
  EXPECT_GT(e.values[2], 0.0);
  EXPECT_LE(e.values[0] / e.values[2], cap * (1 + 1e-5));
}

TEST(Domain, LeavesOutZeroNonFiniteAndNegativeDefiniteTensors) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const std::vector<SymTensor3> tensors{diagonal(0, 0, 0), {nan, 0, 0, 1, 0, 1}, {1, 0, 0, inf, 0, 1},
                                        diagonal(-1, -2, -3), diagonal(0, -1, 0), diagonal(1e-3, 1e-3, 1e-3)};
  const MetricFromTensors m = build(tensors);
  EXPECT_EQ(m.inDomain, (std::vector<std::uint8_t>{0, 0, 0, 0, 0, 1}));
  EXPECT_EQ(m.counts.zero, 1u);
  EXPECT_EQ(m.counts.nonFinite, 2u);
  EXPECT_EQ(m.counts.noPositiveEigenvalue, 2u);
  EXPECT_EQ(m.counts.domain, 1u);
  EXPECT_EQ(m.counts.total, 6u);
}

TEST(Domain, HonoursTheMaskAndTheFaThreshold) {
  MetricOptions options;
  options.faThreshold = 0.5;
  const std::vector<SymTensor3> tensors{diagonal(1, 1, 1), diagonal(3, 0.2, 0.2), diagonal(3, 0.2, 0.2)};
  const MetricFromTensors m = buildMetric(tensors, {1, 1, 0}, options);
  EXPECT_EQ(m.inDomain, (std::vector<std::uint8_t>{0, 1, 0}));
  EXPECT_EQ(m.counts.belowFaThreshold, 1u);
  EXPECT_EQ(m.counts.masked, 1u);
}

TEST(Domain, RejectsACapBelowOneAndAMaskOfAnotherSize) {
  MetricOptions options;
  options.maxAnisotropy = 0.5;
  EXPECT_THROW(build({diagonal(1, 1, 1)}, options), std::invalid_argument);
  EXPECT_THROW(buildMetric({diagonal(1, 1, 1)}, {1, 1}, {}), std::invalid_argument);
}

TEST(FractionalAnisotropy, IsZeroForIsotropicOneForALineAndAboveOneWithANegativeEigenvalue) {
  EXPECT_NEAR(fractionalAnisotropy({2, 2, 2}), 0.0, 1e-12);
  EXPECT_NEAR(fractionalAnisotropy({1, 0, 0}), 1.0, 1e-12);
  EXPECT_GT(fractionalAnisotropy({1, 0, -0.5}), 1.0);
  EXPECT_NEAR(fractionalAnisotropy({1.7e-3, 0.3e-3, 0.3e-3}), 0.8, 0.01);
}

}  // namespace
// Building the metric reports to an Interrupter (start, 0 %, 100 %, end)
// and stops when asked, with Cancelled: there is no partial metric.
TEST(MetricInterruption, BuildingTheMetricReportsAndCanBeStopped) {
  struct Recorder : Interrupter {
    std::vector<std::string> events;
    bool stop = false;
    void start(const char* name) override { events.push_back(std::string("start ") + name); }
    void end() override { events.push_back("end"); }
    bool wasInterrupted(int percent) override {
      events.push_back(std::to_string(percent));
      return stop;
    }
  };
  const std::vector<SymTensor3> tensors(5000, SymTensor3{1, 0, 0, 2, 0, 3});
  Recorder all;
  EXPECT_EQ(buildMetric(tensors, {}, MetricOptions{}, &all).counts.domain, 5000u);
  EXPECT_EQ(all.events, (std::vector<std::string>{"start metric", "0", "100", "end"}));
  Recorder stopping;
  stopping.stop = true;
  EXPECT_THROW(buildMetric(tensors, {}, MetricOptions{}, &stopping), Cancelled);
  EXPECT_EQ(stopping.events.back(), "end");
}

}  // namespace stvd::imaging
