// Steiner-point propagation (Lanthier's edge subdivision, adapted to
// anisotropic metrics as in Campen, Heistermann, Kobbelt, "Practical
// Anisotropic Geodesy", SGP 2013, section 5.1): the accurate, slow option
// that converges to the geodesic distance as the number of Steiner points
// grows. docs/steiner.md describes the construction.
//
// Cells are convex polytopes: the cubes between eight neighbouring voxel
// centres of a grid, the tetrahedra of a mesh, or the polygon faces of a
// surface. Their boundaries are
// sampled by Steiner points (M per cell edge and a lattice of the same
// spacing inside every face, see below), and Dijkstra runs over the graph
// that joins every two boundary points of a cell by the straight segment
// through the cell, measured with that cell's norm. The graph is implicit:
// neighbours are generated from the cell structure when a point is
// finalised, so memory grows with the number of points, not with the number
// of segments (which grows with the fourth power of M).
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/cell_mesh/tetrahedral_cells.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {

/// Index of a point of the Steiner graph: original vertices and Steiner points.
using SteinerPointId = std::uint32_t;

/// Largest supported number of Steiner points per cell edge.
inline constexpr int kMaxSteinerPoints = 16;

struct SteinerOptions {
  /// M: Steiner points per cell edge, 1..kMaxSteinerPoints. In 3D every
  /// face also gets the interior points of the same lattice (M x M on a
  /// square face, M (M - 1) / 2 on a triangle), so a path can cross a face
  /// anywhere to within 1 / (M + 1) of the edge length. On surfaces the
  /// cells are the faces and a path crosses their edges: edge points only.
  int steinerPoints = 4;
  /// Stop once the next point to finalise is farther than this.
  double maxDistance = std::numeric_limits<double>::infinity();
  /// When not empty: stop as soon as all these original vertices are final.
  std::vector<VertexId> targets;
  /// Also return the distances at all Steiner points (pointDistance).
  bool keepPointDistances = false;
  /// Called about every 65536 finalised graph points; return false to
  /// cancel. finalizedVertices and domainVertices count original vertices
  /// (voxels, mesh vertices), frontDistance is that of the last point.
  std::function<bool(const PropagationProgress&)> progress;
};

struct SteinerPropagationResult : PropagationResult {
  // Inherited, per original vertex: distance (kUnreachable where not final),
  // termination, finalizedVertices (original vertices made final),
  // relaxedEdges (segments evaluated: one per finalised point and boundary
  // point of each cell around it), peakStateBytes (distances, queue, scratch;
  // not the domain, metric or cell structure). predecessor holds kNoVertex
  // for every vertex: paths through Steiner points are not tracked.

  /// Points of the Steiner graph, original vertices included.
  std::uint64_t graphPoints = 0;
  /// Distance per graph point when options.keepPointDistances, else empty.
  /// Numbering: steinerPointPosition below.
  std::vector<double> pointDistance;
};

/// Points of the Steiner graph over a grid whose domain holds
/// `domainVoxelCount` voxels: each voxel owns 1 + 3M + 3M^2 of them (itself,
/// M on each of three cube edges, M x M on each of three cube faces).
std::uint64_t steinerGridPointCount(std::uint64_t domainVoxelCount, int steinerPoints);

/// An upper estimate of the memory steinerPropagate allocates for a graph of
/// `graphPoints` points over `vertexCount` original vertices (the cells,
/// domain and metric not included): 24 bytes per graph point (its distance,
/// queue slot and entries; 15.6 measured on the sample brain with M = 2),
/// the result's 12 bytes per vertex and 1 MiB. For checking a run against
/// the memory available before it starts.
std::uint64_t steinerMemoryEstimate(std::uint64_t graphPoints, std::uint64_t vertexCount);

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
SteinerPropagationResult steinerPropagate(const VoxelGridDomain& domain,
                                          const MetricField<Norm>& metric,
                                          const std::vector<VertexId>& sources,
                                          const SteinerOptions& options = {});

/// Tetrahedral-mesh version: cells are the tetrahedra, each measured with
/// the mean of the norm parameters at its four vertices; the metric is given
/// per mesh vertex. Throws as the grid version (except for the grid size).
template <class Norm>
SteinerPropagationResult steinerPropagate(const TetrahedralCells& cells,
                                          const MetricField<Norm>& metric,
                                          const std::vector<VertexId>& sources,
                                          const SteinerOptions& options = {});

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
/// Throws as the grid version (except for the grid size).
SteinerPropagationResult steinerPropagate(const SurfaceDomain& surface, const RiemannianMetric& metric,
                                          const std::vector<VertexId>& sources,
                                          const SteinerOptions& options = {});

/// Physical position of graph point p for M Steiner points per edge.
///
/// Grid numbering: S = 1 + 3M + 3M^2 points per voxel of the domain, p = n S
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
/// Mesh numbering: vertices first (p = v), then M points per edge
/// (cells.edges() order, the m-th at m / (M + 1) from the edge's first to its
/// second vertex), then M (M - 1) / 2 points per face (cells.faces() order,
/// barycentric weights (M + 1 - b - c, b, c) / (M + 1) on the face's
/// vertices for b = 1..M-1, c = 1..M-b in that order).
Vec3d steinerPointPosition(const TetrahedralCells& cells, int steinerPoints, SteinerPointId p);
/// Surface numbering: vertices first (p = v), then M points per undirected
/// edge, the edges sorted by (smaller vertex, larger vertex), the m-th point
/// at m / (M + 1) from the smaller to the larger vertex.
Vec3d steinerPointPosition(const SurfaceDomain& surface, int steinerPoints, SteinerPointId p);

/// The norm a cell is measured with, from the parameters at its corners: the
/// arithmetic mean of the corner parameters (tensors; for Randers, tensors
/// and drifts), exact for a constant field and second-order accurate at the
/// cell's centroid for a smooth one. A mean of valid Randers parameters is
/// valid: sqrt(v^T M v) is concave in M, so the mean norm is at least the
/// mean of the corner norms.
template <class Norm>
struct CellNormRule;

template <>
struct CellNormRule<RiemannianNorm> {
  static SymTensor3 params(const SymTensor3* const* corners, int count) {
    SymTensor3 m{0, 0, 0, 0, 0, 0};
    for (int c = 0; c < count; ++c) {
      m.xx += corners[c]->xx, m.xy += corners[c]->xy, m.xz += corners[c]->xz;
      m.yy += corners[c]->yy, m.yz += corners[c]->yz, m.zz += corners[c]->zz;
    }
    const float s = 1.f / static_cast<float>(count);
    return {s * m.xx, s * m.xy, s * m.xz, s * m.yy, s * m.yz, s * m.zz};
  }
};

template <>
struct CellNormRule<RandersNorm> {
  static RandersNorm::EdgeParams params(const RandersNorm::VertexParams* const* corners, int count) {
    const SymTensor3* tensors[8];
    Vec3f omega{0, 0, 0};
    for (int c = 0; c < count; ++c) {
      tensors[c] = &corners[c]->m;
      omega = omega + corners[c]->omega;
    }
    return {CellNormRule<RiemannianNorm>::params(tensors, count),
            (1.f / static_cast<float>(count)) * omega};
  }
};

extern template SteinerPropagationResult steinerPropagate(const VoxelGridDomain&,
                                                          const RiemannianMetric&,
                                                          const std::vector<VertexId>&,
                                                          const SteinerOptions&);
extern template SteinerPropagationResult steinerPropagate(const VoxelGridDomain&,
                                                          const RandersMetric&,
                                                          const std::vector<VertexId>&,
                                                          const SteinerOptions&);
extern template SteinerPropagationResult steinerPropagate(const TetrahedralCells&,
                                                          const RiemannianMetric&,
                                                          const std::vector<VertexId>&,
                                                          const SteinerOptions&);
extern template SteinerPropagationResult steinerPropagate(const TetrahedralCells&,
                                                          const RandersMetric&,
                                                          const std::vector<VertexId>&,
                                                          const SteinerOptions&);

}  // namespace stvd
