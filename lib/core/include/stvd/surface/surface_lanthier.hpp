// Lanthier's method over a polygon surface (lanthier/lanthier_propagation.hpp):
// Steiner points on the edges of its faces.
#pragma once

#include <cstdint>
#include <vector>

#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/types.hpp"

namespace stvd {

/// Surface version: every polygon face is a cell (nothing is triangulated)
/// with M points on each of its edges, shared with the face across the
/// edge; no points inside faces (in 2D a straight line crosses the cells'
/// edges, so edge points suffice for convergence). Every two boundary points
/// of a face are joined by the straight 3D segment between them, measured
/// with the face's norm: the mean of the world tensors at the face's
/// corners. On a planar face the segment lies in the face's plane, where
/// this is the mean tensor restricted to that plane, i.e. the corner tensors'
/// tangential parts projected into the face, as the surface STVD measures an
/// edge with its end points' mean. A non-planar polygon is measured by the
/// 3D chords between its boundary points (slightly short of the surface);
/// a non-convex one also joins points whose segment leaves the polygon
/// (paths may cut across a reflex corner): triangulate such faces first.
/// Only the Riemannian norm (world tensors per vertex, surface_metrics.hpp).
/// Throws as the grid version does (voxel_grid_lanthier.hpp), except for the
/// grid size.
LanthierResult lanthierPropagate(const SurfaceDomain& surface, const RiemannianMetric& metric,
                                          const std::vector<VertexId>& sources,
                                          const LanthierOptions& options = {});

/// Physical position of graph point p for M Steiner points per edge.
///
/// Numbering: vertices first (p = v), then M points per undirected
/// edge, the edges sorted by (smaller vertex, larger vertex), the m-th point
/// at m / (M + 1) from the smaller to the larger vertex.
Vec3d steinerPointPosition(const SurfaceDomain& surface, int steinerPoints, SteinerPointId p);

}  // namespace stvd
