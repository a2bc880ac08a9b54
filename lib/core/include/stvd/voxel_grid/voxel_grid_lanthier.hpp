// Lanthier's method over a voxel grid (lanthier/lanthier_propagation.hpp):
// Steiner points on the cells between voxel centres of the domain's region.
#pragma once

#include <cstdint>
#include <vector>

#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/metric/lattice_table_norm.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {

/// Points of the Steiner graph over a grid whose domain holds
/// `domainVoxelCount` voxels: each voxel owns 1 + 3M + 3M^2 of them (itself,
/// M on each of three cube edges, M x M on each of three cube faces).
std::uint64_t lanthierGridPointCount(std::uint64_t domainVoxelCount, int steinerPoints);

/// Grid version. The graph covers the domain's region, the same region that
/// Dijkstra's steps and STVD's candidates keep to (VoxelConnectivity), so
/// every method reaches the same voxels. Its cells are the cubes whose eight
/// corners are voxel centres inside the domain (image and mask), every grid
/// edge between two domain voxels (a one-voxel strand or tunnel, and the
/// edges of the cubes), where the domain is thinner than a cube the squares
/// with four domain corners that lie in no such cube (a one-voxel sheet, or
/// a single-slice image), and, as the domain's connectivity joins them, the
/// diagonals between domain voxels that touch only along an edge (Edges) or
/// at a corner (Corners). A cube with a corner outside the mask is not a
/// cell, so paths never pass through it, which is what makes masked voxels
/// obstacles. Each cell is measured with the mean of the norm parameters at
/// its corners (CellNormRule: 8, 4 or 2), an edge as Dijkstra measures it,
/// so no distance exceeds Dijkstra's on the 6-neighbourhood. A domain
/// voxel that belongs to no cell is reached only if it is a source. The
/// domain's stencil is not used. Spacing and direction cosines are honoured;
/// distances are in millimetres.
///
/// Throws std::invalid_argument for a metric of the wrong size, no source, a
/// source or target outside the domain, M out of range, a NaN maximum
/// distance, or a graph with more points than 32-bit indices can number.
template <class Norm>
LanthierResult lanthierPropagate(const VoxelGridDomain& domain,
                                          const MetricField<Norm>& metric,
                                          const std::vector<VertexId>& sources,
                                          const LanthierOptions& options = {});

/// Physical position of graph point p for M Steiner points per edge.
///
/// Numbering: S = 1 + 3M + 3M^2 points per voxel of the domain, p = n S
/// + slot, where n numbers the domain's voxels in index order (n = v, the
/// voxel index, without a mask; voxels outside the mask carry no points);
/// slot 0 is the voxel centre, slots 1 + a M + (m - 1) are the points
/// m / (M + 1) of the way along the grid edge from v to v + e_a (a = 0, 1, 2
/// the index axes i, j, k; m = 1..M), and slots 1 + 3M + a M^2 + (m_b - 1) M
/// + (m_c - 1) are the face points (m_b, m_c) / (M + 1) of the square
/// spanned at v by the two axes b < c other than a. The cells of every kind
/// share these points: an edge cell uses the points on it, a square cell the
/// edge and face points on it, and a diagonal cell only its two voxel
/// centres. Points that lie in no cell (on the image's last layer along
/// their axis, or outside the domain's region) are never reached.
Vec3d steinerPointPosition(const VoxelGridDomain& domain, int steinerPoints, SteinerPointId p);

// Compiled in the library (voxel_grid_lanthier.cpp).
extern template LanthierResult lanthierPropagate(const VoxelGridDomain&,
                                                          const RiemannianMetric&,
                                                          const std::vector<VertexId>&,
                                                          const LanthierOptions&);
extern template LanthierResult lanthierPropagate(const VoxelGridDomain&,
                                                          const RandersMetric&,
                                                          const std::vector<VertexId>&,
                                                          const LanthierOptions&);
extern template LanthierResult lanthierPropagate(const VoxelGridDomain&, const MetricField<LatticeTableNorm<2>>&,
                                                 const std::vector<VertexId>&, const LanthierOptions&);

}  // namespace stvd
