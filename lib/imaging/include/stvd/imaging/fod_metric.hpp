// The convexified FOD norm F* (fod_cost.hpp) as a metric of the
// propagation over a voxel grid: per voxel a table of F* along the 26
// neighbour directions, so that a 26-neighbour step costs exactly F* of its
// direction (docs/fod.md, "Propagation").
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "stvd/imaging/fod_cost.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd::imaging {

/// A norm given by its values along the 26 neighbour directions of a grid
/// (a plain struct of floats, as the propagation interpolates norms):
///
/// * a vector along neighbour direction q (index offset (di, dj, dk) in
///   {-1, 0, 1}^3) has length |v| cost[q] (the edge rule: the mean of the two
///   end points' tables, half an edge in each voxel);
/// * any other vector (an STVD candidate) is measured by the gauge of the
///   hull of the 26 points u_q / cost[q]: the cheapest zig-zag of neighbour
///   directions, a path that exists, never below F*.
struct FodStencilNorm {
  struct VertexParams {
    /// Physical vector (LPS, mm) to index offset: (D diag(spacing))^-1, row-major.
    float toIndex[9];
    /// F* along the unit neighbour direction q (order of neighbourDirections26).
    float cost[26];
  };
  using EdgeParams = VertexParams;
  static constexpr bool kEdgeRuleIsMean = true;

  static EdgeParams edgeParams(const VertexParams& a, const VertexParams& b) {
    EdgeParams e;
    for (int i = 0; i < 9; ++i) e.toIndex[i] = 0.5f * (a.toIndex[i] + b.toIndex[i]);
    for (int q = 0; q < 26; ++q) e.cost[q] = 0.5f * (a.cost[q] + b.cost[q]);
    return e;
  }
  static float length(const EdgeParams& g, float x, float y, float z) {
    const float len = std::sqrt(x * x + y * y + z * z);
    if (len == 0.f) return 0.f;
    const float fi = g.toIndex[0] * x + g.toIndex[1] * y + g.toIndex[2] * z;
    const float fj = g.toIndex[3] * x + g.toIndex[4] * y + g.toIndex[5] * z;
    const float fk = g.toIndex[6] * x + g.toIndex[7] * y + g.toIndex[8] * z;
    const float ri = std::nearbyint(fi), rj = std::nearbyint(fj), rk = std::nearbyint(fk);
    if (std::abs(fi - ri) < 1e-3f && std::abs(fj - rj) < 1e-3f && std::abs(fk - rk) < 1e-3f &&
        std::abs(ri) <= 1.f && std::abs(rj) <= 1.f && std::abs(rk) <= 1.f) {
      int q = static_cast<int>((rk + 1) * 9 + (rj + 1) * 3 + (ri + 1));
      if (q > 13) --q;  // the centre (0, 0, 0) is no direction
      return len * g.cost[q];
    }
    return offStencilLength(g, x, y, z);
  }
  /// The gauge of the hull of the 26 points along a vector that is no
  /// neighbour step.
  static float offStencilLength(const EdgeParams& g, float x, float y, float z);
  static std::string invalidReason(const VertexParams& p);
};

using FodStencilMetric = MetricField<FodStencilNorm>;

/// fodStencilMetric hands voxels to its threads in blocks of this many
/// (so a grid of n voxels keeps at most ceil(n / block) threads busy).
inline constexpr std::size_t kFodMetricBlockVoxels = 256;

/// The metric of an FOD on its own grid: F* of `sampler` (default
/// sampling directions of the field's grid) along the 26 neighbour
/// directions of every voxel with a non-zero `inDomain` entry (every voxel
/// when null; the others get the floor's isotropic cost), computed on
/// `threads` threads (0: one per core); the table is the same for any count.
///
/// `interrupter` (may be null) hears the table as an operation of its own,
/// "FOD table": start, 0 %, then after blocks of voxels at least every
/// `progressInterval` seconds (percent: the share of the blocks done), 100 %,
/// end. The reports come one at a time, from whichever of the threads
/// finished a block. When it asks to stop, no further block starts and the
/// call throws stvd::Cancelled ("FOD table was interrupted"): a table with
/// voxels left out is no metric.
FodStencilMetric fodStencilMetric(const FodCostSampler& sampler, const std::vector<std::uint8_t>* inDomain = nullptr,
                                  unsigned threads = 1, Interrupter* interrupter = nullptr,
                                  double progressInterval = kDefaultInterruptInterval);

/// F* of every voxel along the query vectors (LPS, unit or not; F* is
/// 1-homogeneous): result[v * queries.size() + q], for voxels with a
/// non-zero `inDomain` entry (every voxel when null), the others |query|
/// times the floor's isotropic cost; on `threads` threads (0: one per core),
/// the same for any count. The per-voxel table every FOD metric is made of
/// (fodStencilMetric's 26 directions, fod_segment_norm.hpp's lattices); a
/// query whose opposite came earlier takes its value. Progress and
/// interruption as fodStencilMetric's.
std::vector<float> convexifiedFodTable(const FodCostSampler& sampler, const std::vector<Vec3d>& queries,
                                       const std::vector<std::uint8_t>* inDomain = nullptr, unsigned threads = 1,
                                       Interrupter* interrupter = nullptr,
                                       double progressInterval = kDefaultInterruptInterval);

}  // namespace stvd::imaging

namespace stvd {
// Compiled in the imaging adapter (fod_metric.cpp).
extern template PropagationResult propagate(const VoxelGridDomain&, const imaging::FodStencilMetric&,
                                            const std::vector<VertexId>&, const PropagationOptions&);
}  // namespace stvd
