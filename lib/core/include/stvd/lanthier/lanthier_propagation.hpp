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

#include "stvd/metric/lattice_table_norm.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/types.hpp"

namespace stvd {

/// Index of a point of the Steiner graph: original vertices and Steiner points.
using SteinerPointId = std::uint32_t;

/// Largest supported number of Steiner points per cell edge.
inline constexpr int kMaxSteinerPoints = 16;

struct LanthierOptions {
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
  /// Called as PropagationOptions::progress is (at the start, at least
  /// every progressInterval seconds, at the end; a cancelled run holds no
  /// distances); return false to cancel. finalizedVertices and
  /// domainVertices count original vertices (voxels, mesh vertices),
  /// frontDistance is that of the last point. The setup before the
  /// propagation (the Steiner cells and the propagation's state: 0.1 s for
  /// the 29 million points of the sample brain with M = 8) reports here
  /// first, with no vertex final and fraction 0; cancelled there, the run
  /// returns as a cancelled run does, before any point is final.
  std::function<bool(const PropagationProgress&)> progress;
  /// The same reports for an Interrupter: first the setup, an operation of
  /// its own ("Steiner cells", 0 to 100 %), then "Steiner-point
  /// propagation".
  Interrupter* interrupter = nullptr;
  double progressInterval = kDefaultInterruptInterval;
};

struct LanthierResult : PropagationResult {
  // Inherited, per original vertex: distance (kUnreachable where not final),
  // termination, finalizedVertices (original vertices made final),
  // relaxedEdges (segments evaluated: one per finalised point and boundary
  // point of each cell around it), peakStateBytes (distances, queue, scratch;
  // not the domain, metric or cell structure). predecessor holds kNoVertex
  // for every vertex and hasPredecessors is false: paths through Steiner
  // points are not tracked, and tracing a path from this result is refused
  // (std::invalid_argument). Trace paths from a Dijkstra or STVD result.

  /// Points of the Steiner graph, original vertices included.
  std::uint64_t graphPoints = 0;
  /// Distance per graph point when options.keepPointDistances, else empty.
  /// Numbering: steinerPointPosition below.
  std::vector<double> pointDistance;
};

// The entry points are declared per domain, beside the domain:
// voxel_grid/voxel_grid_lanthier.hpp, cell_mesh/cell_mesh_lanthier.hpp and
// surface/surface_lanthier.hpp.

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

/// A tabulated norm's cell: the mean of the corner tables (and index
/// transforms), exact for a constant field as for the other norms.
template <int Order>
struct CellNormRule<LatticeTableNorm<Order>> {
  using Norm = LatticeTableNorm<Order>;
  static typename Norm::EdgeParams params(const typename Norm::VertexParams* const* corners, int count) {
    typename Norm::EdgeParams e{};
    const float s = 1.f / static_cast<float>(count);
    for (int c = 0; c < count; ++c) {
      for (int i = 0; i < 9; ++i) e.toIndex[i] += s * corners[c]->toIndex[i];
      for (int q = 0; q < Norm::kCount; ++q) e.cost[q] += s * corners[c]->cost[q];
    }
    return e;
  }
};

}  // namespace stvd
