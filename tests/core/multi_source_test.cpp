// Several sources at once.
//
// Dijkstra's distance is the minimum over edge paths from any source, and
// rounded addition is monotone, so the multi-source run is exactly the
// element-wise minimum of the single-source runs.
//
// STVD is not exactly separable: the value of a vertex depends on the
// predecessor chains of its finalised neighbours, and where the fronts of two
// sources meet those chains mix. Away from that meeting zone every vertex a
// value depends on lies in the same source's region, so the multi-source run
// repeats the single-source run step for step; inside the zone the two
// differ by up to the method's own error, in either direction (neither
// d_multi <= min(single) nor the converse holds there).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <vector>

#include "scenes.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd {
namespace {

template <class Domain, class Norm>
std::vector<PropagationResult> singleSourceRuns(const Domain& domain, const MetricField<Norm>& metric,
                                                const std::vector<VertexId>& sources,
                                                const PropagationOptions& options) {
  std::vector<PropagationResult> runs;
  for (VertexId s : sources) runs.push_back(propagate(domain, metric, {s}, options));
  return runs;
}

template <class Domain, class Norm>
void expectDijkstraIsMinimumOfSingleRuns(const Domain& domain, const MetricField<Norm>& metric,
                                         const std::vector<VertexId>& sources) {
  PropagationOptions o;
  o.method = Method::Dijkstra;
  const PropagationResult multi = propagate(domain, metric, sources, o);
  const std::vector<PropagationResult> singles = singleSourceRuns(domain, metric, sources, o);
  std::size_t finite = 0;
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    double nearest = kUnreachable;
    for (const PropagationResult& r : singles) nearest = std::min(nearest, r.distance[v]);
    ASSERT_EQ(std::memcmp(&multi.distance[v], &nearest, sizeof(double)), 0)
        << "vertex " << v << ": " << multi.distance[v] << " vs " << nearest;
    finite += nearest < kUnreachable ? 1 : 0;
  }
  EXPECT_GT(finite, domain.domainVertexCount() / 2);
}

TEST(MultiSource, DijkstraIsExactlyTheMinimumOfSingleSourceRuns) {
  const VoxelGridDomain domain(test::obliqueGrid({40, 40, 40}), Stencil::full26());
  const RiemannianMetric metric(test::smoothVaryingTensors(domain));
  expectDijkstraIsMinimumOfSingleRuns(
      domain, metric,
      {domain.vertexAt(5, 5, 5), domain.vertexAt(30, 20, 10), domain.vertexAt(12, 33, 30)});
}

TEST(MultiSource, DijkstraIsExactlyTheMinimumWithMaskAndRandersNorm) {
  const GridGeometry g = test::obliqueGrid({32, 32, 32});
  // Two disjoint balls: the source in each reaches only its own ball.
  std::vector<std::uint8_t> mask = test::ballMask(g, {9, 9, 9}, 8.0);
  const std::vector<std::uint8_t> second = test::ballMask(g, {22, 22, 22}, 9.0);
  for (std::size_t v = 0; v < mask.size(); ++v) mask[v] = mask[v] || second[v];
  const VoxelGridDomain domain(g, Stencil::full26(), mask);
  const RandersMetric metric(test::smoothVaryingRanders(domain), &domain.mask());
  expectDijkstraIsMinimumOfSingleRuns(
      domain, metric,
      {domain.vertexAt(9, 9, 9), domain.vertexAt(20, 22, 25), domain.vertexAt(25, 20, 20)});
}

// Away from the meeting zone (vertices whose second-nearest source is at
// least 20 % farther than the nearest) the multi-source run equals the
// single-source minimum bit for bit, with the chain of edges alone and with
// the default any-angle ancestor. It did not always: a vertex whose screened
// key was raised once measured (FrontQueue::requeueMin) could reach the top
// of the queue again by an entry left from its earlier, lower key, and be
// settled there out of order; whether such an entry was left behind depends
// on where the queue's buckets lie, and so on the other sources' fronts.
// Measured before the fix (separated vertices that differed): the three
// sources below 0 of 46472; the second set 1732 of 57478 with the default
// ancestor (k = 8, by up to 4.4 %); the third set 1362 of 60989 with the
// chain alone at k = 12. After it: 0 in each. Nearer the meeting zone the
// two differ by up to the method's own error, in either direction.
constexpr double kSeparatedMargin = 0.2;
constexpr double kMaxDeviationNearBoundary = 0.025;
constexpr double kMinEqualFraction = 0.982;

void expectStvdNearlyMinimumOfSingleRuns(const std::vector<VoxelIndex>& seeds, int k, int anyAngleAncestors) {
  const VoxelGridDomain domain(test::obliqueGrid({40, 40, 40}), Stencil::full26());
  const RiemannianMetric metric(test::smoothVaryingTensors(domain));
  std::vector<VertexId> sources;
  for (const VoxelIndex& s : seeds) sources.push_back(domain.vertexAt(s.i, s.j, s.k));
  PropagationOptions o;
  o.method = Method::ShortTermVectorDijkstra;
  o.k = k;
  o.anyAngleAncestors = anyAngleAncestors;
  const PropagationResult multi = propagate(domain, metric, sources, o);
  const std::vector<PropagationResult> singles = singleSourceRuns(domain, metric, sources, o);

  std::size_t equal = 0, separated = 0, separatedDiffering = 0;
  double largestDeviation = 0.0;
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    std::vector<double> d;
    for (const PropagationResult& r : singles) d.push_back(r.distance[v]);
    std::sort(d.begin(), d.end());
    if (d[0] == 0.0) {
      EXPECT_EQ(multi.distance[v], 0.0);
      continue;
    }
    equal += multi.distance[v] == d[0] ? 1 : 0;
    largestDeviation = std::max(largestDeviation, std::abs(multi.distance[v] - d[0]) / d[0]);
    if (d[1] >= (1.0 + kSeparatedMargin) * d[0]) {
      ++separated;
      separatedDiffering += multi.distance[v] == d[0] ? 0 : 1;
      EXPECT_EQ(multi.distance[v], d[0]) << "vertex " << v << " far from the meeting zone";
    }
  }
  const std::size_t count = domain.vertexCount() - sources.size();
  std::printf("[ measured ] multi-source STVD k=%d, %d any-angle ancestors: %zu of %zu equal, %zu separated "
              "(%zu of them differ), largest deviation %.4f\n",
              k, anyAngleAncestors, equal, count, separated, separatedDiffering, largestDeviation);
  EXPECT_GE(separated, count / 2);
  EXPECT_GE(static_cast<double>(equal), kMinEqualFraction * count);
  EXPECT_LE(largestDeviation, kMaxDeviationNearBoundary);
}

TEST(MultiSource, StvdEqualsMinimumOfSingleRunsAwayFromWhereFrontsMeet) {
  const std::vector<VoxelIndex> seeds{{5, 5, 5}, {30, 20, 10}, {12, 33, 30}};
  expectStvdNearlyMinimumOfSingleRuns(seeds, 8, 0);
  expectStvdNearlyMinimumOfSingleRuns(seeds, 8, kDefaultAnyAngleAncestors);
}

TEST(MultiSource, NoVertexIsSettledByAnEntryLeftFromAnEarlierKey) {
  expectStvdNearlyMinimumOfSingleRuns({{8, 30, 5}, {33, 8, 20}, {20, 20, 35}}, 8, kDefaultAnyAngleAncestors);
  expectStvdNearlyMinimumOfSingleRuns({{19, 19, 19}, {2, 37, 3}}, 12, 0);
}

}  // namespace
}  // namespace stvd
