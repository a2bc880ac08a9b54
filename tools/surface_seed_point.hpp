// A seed given as a point on a polygon surface (`stvd distance MESH
// --seed-point X,Y,Z`): its nearest vertex, or the point itself inserted
// into the mesh as a vertex.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "stvd/surface_io/surface_mesh_io.hpp"
#include "stvd/types.hpp"

namespace stvd::tool {

/// The point of a surface closest to a given point.
struct SurfacePoint {
  Vec3d closest;
  double distance = 0.0;  ///< from the given point to `closest`
  std::size_t face = 0;   ///< the face it lies on
  /// The corners that carry it, with barycentric weights summing to 1:
  /// one corner (it is that vertex), two (it lies on the segment between
  /// them) or three (inside a triangle of the face's fan from its first
  /// corner). Weights below 1e-9 count as 0.
  std::vector<std::pair<VertexId, double>> weights;
};

/// The closest point over all faces (polygons are measured as the fan of
/// triangles from their first corner).
SurfacePoint closestSurfacePoint(const surface_io::SurfaceMesh& mesh, Vec3d point);

/// The vertex nearest to `point` (Euclidean; the first of equals).
VertexId nearestVertex(const surface_io::SurfaceMesh& mesh, Vec3d point);

/// Makes `p` a vertex of `mesh` and returns it: a point on a vertex is that
/// vertex (the mesh is unchanged); a point on an edge of a polygon is
/// appended as a vertex and inserted into that edge in both faces that
/// share it; a point inside a face is appended and the face becomes the fan
/// of triangles from it to the face's edges (orientation kept).
/// `faceOrigin` (one entry per face of `mesh`) says which face of the file
/// each face comes from; it is updated with the faces.
VertexId insertSurfacePoint(surface_io::SurfaceMesh& mesh, const SurfacePoint& p,
                            std::vector<std::size_t>& faceOrigin);

}  // namespace stvd::tool
