// Non-manifold polygon meshes split into manifold sheets, and distances that
// pass between the sheets where the input joined them (docs/surfaces.md,
// "Non-manifold meshes").
//
// Range scans and CAD exports have edges shared by three or more faces, and
// vertices whose faces form several fans (a bow tie, a pinched boundary, a
// face hanging from an edge). SurfaceDomain needs a 2-manifold, so such a
// mesh is split: at each vertex, the faces that are joined around it
// through manifold edges (two faces) stay together and every other group
// gets a copy of the vertex; of the faces of an edge with more than two,
// the first two that run along it in opposite directions (else the first
// two) stay joined across it, the others are cut off. The copies of a
// vertex are the same point of the input: propagateOverSheets makes their
// distances one, so a path may go from any sheet to any other through a
// vertex they shared. Every distance is still the length of a path on the
// input surface; a path that crosses a split edge does so at one of the
// edge's end points (a shortest path through the edge's interior is not
// taken there, so distances beyond it can only be longer than exact).
#pragma once

#include <cstddef>
#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/metric/norms.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/types.hpp"

namespace stvd {

struct ManifoldSheets {
  /// The split mesh: the input's vertices first (same numbers), then the
  /// copies; the faces in input order with their corners renumbered.
  std::vector<Vec3d> points;
  PolygonList faces;
  /// For each vertex of the split mesh, the input vertex it is (itself for
  /// the first inputVertexCount).
  std::vector<VertexId> original;
  std::size_t inputVertexCount = 0;
  /// Edges of the input shared by more than two faces, faces cut off from
  /// them, input vertices that became several, and the copies made.
  std::size_t nonManifoldEdges = 0;
  std::size_t detachedFaces = 0;
  std::size_t splitVertices = 0;
  std::size_t addedVertices = 0;

  bool changed() const { return addedVertices != 0; }
  /// All copies of input vertex v (v itself first).
  std::vector<VertexId> copiesOf(VertexId v) const;
};

/// Splits `faces` over `points` into manifold sheets; a manifold mesh comes
/// back unchanged (changed() false). Faces must have at least 3 distinct
/// vertices in range (SurfaceDomain's messages otherwise). Orientation is
/// left to SurfaceDomain, which flips faces per component.
ManifoldSheets splitIntoManifoldSheets(const std::vector<Vec3d>& points, const PolygonList& faces);

/// The surface of a mesh that may be non-manifold: the mesh as it is when
/// SurfaceDomain takes it (`sheets` then unchanged, without copies of the
/// points and faces: only `original` and `inputVertexCount` are set), else
/// its manifold sheets. So a manifold mesh costs no split. Throws the
/// SurfaceError of the mesh as given when splitting changes nothing, or
/// that of the sheets (a Möbius strip stays one).
SurfaceDomain surfaceOfSheets(const std::vector<Vec3d>& points, const PolygonList& faces, ManifoldSheets& sheets);

/// Distances over the split surface from `sources` (vertices of the split
/// mesh; pass every copy of a seed), with the copies of each input vertex
/// joined: the propagation is repeated with the copies whose distance is
/// the shortest of their group as sources at that distance until no group
/// improves, and each vertex keeps its shortest distance of all runs (every
/// one the length of a path: to a copy, then on from it). All copies of an
/// input vertex end with the same distance. `runs`, when given, receives
/// how many propagations were needed.
PropagationResult propagateOverSheets(const SurfaceDomain& surface, const RiemannianMetric& metric,
                                      const ManifoldSheets& sheets, const std::vector<VertexId>& sources,
                                      const PropagationOptions& options, int* runs = nullptr);

}  // namespace stvd
