// Accuracy under a constant Riemannian metric on an oblique voxel grid.
//
// With a constant tensor G every straight segment is a geodesic and the grid
// box is convex, so the exact distance from the source s is
//   d(x) = sqrt((x - s)^T G (x - s))
// in physical coordinates. The grid has anisotropic spacing, direction
// cosines that are a genuine rotation and a non-zero origin, and G's long
// axis is oblique to both the physical axes and the index axes, so none of
// the geometry can cancel out.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "exact_metrics.hpp"
#include "method_cases.hpp"
#include "relative_error.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd {
namespace {

using test::RelativeErrors;

GridGeometry obliqueAnisotropicGrid() {
  return test::orientedGrid({48, 32, 24}, {1.0, 1.5, 2.0}, {-31.5, 12.25, 107.0},
                            test::rotation({1.0, -2.0, 0.5}, 0.7));
}

const Vec3d kLongAxis{0.3, -0.8, 0.52};  // physical direction of G's largest eigenvalue

RelativeErrors relativeErrors(const VoxelGridDomain& domain, const test::Mat3& g,
                              VertexId source, const PropagationResult& result) {
  RelativeErrors errors;
  const Vec3d s = domain.physicalPoint(source);
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    if (v == source) continue;
    errors.add(result.distance[v], test::tensorNorm(g, domain.physicalPoint(v) - s));
  }
  return errors;
}

/// Mean and maximum relative error bounds of one method at one anisotropy.
struct Tolerance {
  double mean;
  double max;
};

struct ConstantMetricCase {
  double gamma;
  Tolerance dijkstra;
  Tolerance stvdK8;
  Tolerance stvdDefault;  // the default options: k = 6, segment measure
  /// Dijkstra's mean error divided by STVD's (k = 8) must be at least this.
  double minImprovement;
};

// Measured relative errors on this grid and source (Release, x86-64; the
// larger of the AVX2 and the baseline build of the kernel, whose different
// float rounding breaks lattice ties differently):
//            Dijkstra 26        STVD k = 8 (paper)  STVD default (k = 6, segment)
//   gamma    mean    max        mean     max        mean     max
//    1       0.119   0.218      0.00198  0.0220     0.00324  0.0284
//   10       0.335   3.61       0.00930  0.164      0.0112   0.184
//   50       0.759  19.4        0.0187   3.74       0.0298   6.15
// (The default before the segment measure, the paper's rule at k = 5:
// 0.00529, 0.0165, 0.0299 mean.)
// (With a constant norm both rules give every candidate the same length up
// to rounding; the two columns differ through lattice ties, which rounding
// breaks differently, as between the AVX2 and the baseline kernel.)
// STVD's maxima sit next to the source. At gamma 50 the worst voxel is two
// edges from it, almost on the cheap plane of G (exact 2.85); every voxel
// adjacent to both has a distance of 25 or more, so the voxel is finalised
// at 13.5 through another chain before any of them could offer the straight
// vector to the source.
// Each bound below is about 1.3-1.4 times the measured figure, the
// improvement bound about the measured ratio (60, 36, 41) divided by 1.5.
const ConstantMetricCase kCases[] = {
    //  gamma  Dijkstra      STVD k=8         STVD default      Dijkstra/STVD
    {1.0, {0.16, 0.29}, {0.0028, 0.031}, {0.0046, 0.040}, 40.0},
    {10.0, {0.45, 4.8}, {0.013, 0.23}, {0.016, 0.26}, 24.0},
    {50.0, {1.0, 26.0}, {0.026, 5.2}, {0.042, 8.6}, 27.0},
};

class ConstantMetricAccuracy : public ::testing::TestWithParam<ConstantMetricCase> {
 protected:
  void SetUp() override {
    gamma_ = GetParam().gamma;
    g_ = test::uniaxialTensor(gamma_, kLongAxis);
    source_ = domain_.vertexAt(20, 13, 10);
  }
  RelativeErrors measure(const PropagationOptions& options, const std::string& label) {
    const RiemannianMetric metric =
        RiemannianMetric::constant(domain_.vertexCount(), test::toSymTensor(g_));
    const PropagationResult result = propagate(domain_, metric, {source_}, options);
    EXPECT_EQ(result.termination, Termination::Completed);
    const RelativeErrors errors = relativeErrors(domain_, g_, source_, result);
    test::reportMeasurement("gamma " + std::to_string(static_cast<int>(gamma_)) + " " + label,
                            errors);
    EXPECT_EQ(errors.unreached(), 0u) << label;
    // Every candidate either method forms is the length of a polygon from the
    // source, and a constant norm obeys the triangle inequality, so neither
    // method can undercut the exact distance, up to float rounding: the
    // tensor is stored in single precision, which perturbs v^T G v by up to
    // a few units of 2^-24 times gamma^2 |v|^2, most visible for the short
    // axis (measured down to -3.7e-7, -3.7e-6, -2.2e-5 for gamma 1, 10, 50).
    const double roundingSlack = 1e-6 + 3.0 * gamma_ * gamma_ * 0x1.0p-24;
    EXPECT_GE(errors.minSigned(), -roundingSlack) << label;
    return errors;
  }

  VoxelGridDomain domain_{obliqueAnisotropicGrid(), Stencil::full26()};
  double gamma_ = 1.0;
  test::Mat3 g_;
  VertexId source_ = 0;
};

using test::withMethod;

TEST_P(ConstantMetricAccuracy, DijkstraErrorIsWithinItsStatedBound) {
  const RelativeErrors e = measure(withMethod(Method::Dijkstra), "Dijkstra 26");
  EXPECT_LE(e.mean(), GetParam().dijkstra.mean);
  EXPECT_LE(e.max(), GetParam().dijkstra.max);
}

TEST_P(ConstantMetricAccuracy, StvdWithDepth8IsWithinItsStatedBound) {
  const RelativeErrors e = measure(withMethod(Method::ShortTermVectorDijkstra, 8), "STVD k=8 26");
  EXPECT_LE(e.mean(), GetParam().stvdK8.mean);
  EXPECT_LE(e.max(), GetParam().stvdK8.max);
}

TEST_P(ConstantMetricAccuracy, StvdWithDefaultDepthIsWithinItsStatedBound) {
  // The bounds were measured for k = 6 and the segment measure; a new
  // default needs new measurements.
  ASSERT_EQ(kDefaultMemoryDepth, 6) << "re-measure the default-k bounds in this file";
  ASSERT_EQ(kDefaultChainMeasure, ChainMeasure::Segment) << "re-measure the default-k bounds in this file";
  const RelativeErrors e = measure(PropagationOptions{}, "STVD default (k=6, segment) 26");
  EXPECT_LE(e.mean(), GetParam().stvdDefault.mean);
  EXPECT_LE(e.max(), GetParam().stvdDefault.max);
}

TEST_P(ConstantMetricAccuracy, StvdIsSeveralTimesMoreAccurateThanDijkstra) {
  const RelativeErrors dijkstra = measure(withMethod(Method::Dijkstra), "Dijkstra 26");
  const RelativeErrors stvd = measure(withMethod(Method::ShortTermVectorDijkstra, 8), "STVD k=8 26");
  EXPECT_GE(dijkstra.mean(), GetParam().minImprovement * stvd.mean());
}

INSTANTIATE_TEST_SUITE_P(Gamma, ConstantMetricAccuracy, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<ConstantMetricCase>& info) {
                           return "gamma" + std::to_string(static_cast<int>(info.param.gamma));
                         });

}  // namespace
}  // namespace stvd
