// The convexified FOD norm F* (fod_cost.hpp) for any segment vector: what
// STVD's segment measure and Lanthier's cells measure on FOD metrics
// (docs/fod.md, "STVD and Lanthier").
//
// Per voxel a table of F* along the lattice directions of order n of the
// grid (LatticeTableNorm: the offsets whose largest index component is n),
// interpolated linearly over the cube's faces. Along the 26 neighbour
// directions it is the tabulated F* exactly (they are lattice directions
// for every n); elsewhere it is never below the tabulated norm (a linear
// interpolation of a convex function), so every length STVD or Lanthier
// reports is still the F-length of a zig-zag that exists.
#pragma once

#include <cstdint>
#include <vector>

#include "stvd/imaging/fod_cost.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/metric/lattice_table_norm.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd::imaging {

/// The lattice order of FOD segment metrics: 2 (49 values of F* per voxel;
/// docs/fod.md, "STVD and Lanthier", gives the measurements behind it).
inline constexpr int kFodLatticeOrder = 2;

using FodSegmentNorm = LatticeTableNorm<kFodLatticeOrder>;
using FodSegmentMetric = MetricField<FodSegmentNorm>;

/// The physical vectors A d (LPS, mm) of the table entries of
/// LatticeTableNorm<Order> on `geometry`, in the table's order.
template <int Order>
std::vector<Vec3d> latticeVectors(const GridGeometry& geometry);

/// The FOD's metric for any segment vector: per voxel with a non-zero
/// `inDomain` entry (every voxel when null) F* of `sampler` along
/// latticeVectors<Order>, computed on `threads` threads (0: one per core;
/// the table is the same for any count); the other voxels get the floor's
/// isotropic cost.
template <int Order>
MetricField<LatticeTableNorm<Order>> fodLatticeMetric(const FodCostSampler& sampler,
                                                      const std::vector<std::uint8_t>* inDomain = nullptr,
                                                      unsigned threads = 1, Interrupter* interrupter = nullptr,
                                                      double progressInterval = kDefaultInterruptInterval);

inline FodSegmentMetric fodSegmentMetric(const FodCostSampler& sampler,
                                         const std::vector<std::uint8_t>* inDomain = nullptr, unsigned threads = 1,
                                         Interrupter* interrupter = nullptr,
                                         double progressInterval = kDefaultInterruptInterval) {
  return fodLatticeMetric<kFodLatticeOrder>(sampler, inDomain, threads, interrupter, progressInterval);
}

}  // namespace stvd::imaging

namespace stvd {
// Compiled in the imaging adapter (fod_segment_norm.cpp) for the order used.
extern template PropagationResult propagate(const VoxelGridDomain&, const imaging::FodSegmentMetric&,
                                            const std::vector<VertexId>&, const PropagationOptions&);
}  // namespace stvd
