// Lanthier's method over a tetrahedral mesh (lanthier/lanthier_propagation.hpp):
// Steiner points on the edges and faces of its tetrahedra (TetrahedralCells).
#pragma once

#include <cstdint>
#include <vector>

#include "stvd/cell_mesh/tetrahedral_cells.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/types.hpp"

namespace stvd {

/// Tetrahedral-mesh version: cells are the tetrahedra, each measured with
/// the mean of the norm parameters at its four vertices; the metric is given
/// per mesh vertex. Throws as the grid version does (voxel_grid_lanthier.hpp),
/// except for the grid size.
template <class Norm>
LanthierResult lanthierPropagate(const TetrahedralCells& cells,
                                          const MetricField<Norm>& metric,
                                          const std::vector<VertexId>& sources,
                                          const LanthierOptions& options = {});

/// Physical position of graph point p for M Steiner points per edge.
///
/// Numbering: vertices first (p = v), then M points per edge
/// (cells.edges() order, the m-th at m / (M + 1) from the edge's first to its
/// second vertex), then M (M - 1) / 2 points per face (cells.faces() order,
/// barycentric weights (M + 1 - b - c, b, c) / (M + 1) on the face's
/// vertices for b = 1..M-1, c = 1..M-b in that order).
Vec3d steinerPointPosition(const TetrahedralCells& cells, int steinerPoints, SteinerPointId p);

// Compiled in the library (cell_mesh_lanthier.cpp).
extern template LanthierResult lanthierPropagate(const TetrahedralCells&,
                                                          const RiemannianMetric&,
                                                          const std::vector<VertexId>&,
                                                          const LanthierOptions&);
extern template LanthierResult lanthierPropagate(const TetrahedralCells&,
                                                          const RandersMetric&,
                                                          const std::vector<VertexId>&,
                                                          const LanthierOptions&);

}  // namespace stvd
