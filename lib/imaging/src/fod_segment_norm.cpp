// The segment metric of an FOD: F* tabulated along a lattice of the grid.
#include "stvd/imaging/fod_segment_norm.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include "stvd/imaging/fod_metric.hpp"
#include "stvd/propagation/propagation_definition.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd::imaging {

template <int Order>
std::vector<Vec3d> latticeVectors(const GridGeometry& geometry) {
  std::vector<Vec3d> v;
  for (int t = 0; t < LatticeTableNorm<Order>::kCount; ++t) {
    const std::array<int, 3> d = LatticeTableNorm<Order>::latticeOffset(t);
    v.push_back(geometry.indexToPhysicalOffset(d[0], d[1], d[2]));
  }
  return v;
}

template <int Order>
MetricField<LatticeTableNorm<Order>> fodLatticeMetric(const FodCostSampler& sampler,
                                                      const std::vector<std::uint8_t>* inDomain, unsigned threads,
                                                      Interrupter* interrupter, double progressInterval) {
  using Norm = LatticeTableNorm<Order>;
  const GridGeometry& g = sampler.field().geometry;
  const std::vector<Vec3d> queries = latticeVectors<Order>(g);
  // F* is 1-homogeneous: its value at A d is the F*-length of the step d.
  const std::vector<float> table = convexifiedFodTable(sampler, queries, inDomain, threads, interrupter, progressInterval);
  float toIndex[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) toIndex[3 * r + c] = static_cast<float>(g.direction[3 * c + r] / g.spacing[r]);
  std::vector<typename Norm::VertexParams> params(g.voxelCount());
  for (std::size_t v = 0; v < params.size(); ++v) {
    std::copy(toIndex, toIndex + 9, params[v].toIndex);
    std::copy(table.begin() + v * Norm::kCount, table.begin() + (v + 1) * Norm::kCount, params[v].cost);
  }
  return MetricField<Norm>(std::move(params), inDomain);
}

template std::vector<Vec3d> latticeVectors<1>(const GridGeometry&);
template std::vector<Vec3d> latticeVectors<2>(const GridGeometry&);
template std::vector<Vec3d> latticeVectors<3>(const GridGeometry&);
template MetricField<LatticeTableNorm<1>> fodLatticeMetric<1>(const FodCostSampler&, const std::vector<std::uint8_t>*,
                                                              unsigned, Interrupter*, double);
template MetricField<LatticeTableNorm<2>> fodLatticeMetric<2>(const FodCostSampler&, const std::vector<std::uint8_t>*,
                                                              unsigned, Interrupter*, double);
template MetricField<LatticeTableNorm<3>> fodLatticeMetric<3>(const FodCostSampler&, const std::vector<std::uint8_t>*,
                                                              unsigned, Interrupter*, double);

}  // namespace stvd::imaging

namespace stvd {
template PropagationResult propagate(const VoxelGridDomain&, const imaging::FodSegmentMetric&,
                                     const std::vector<VertexId>&, const PropagationOptions&);
}  // namespace stvd
