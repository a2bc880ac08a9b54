// A tetrahedral mesh as TetGen writes it: points with attributes, tetrahedra
// with attributes (region numbers among them), and optional boundary faces.
// Plain data in flat arrays; no dependency beyond the core's types.
#pragma once

#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "stvd/errors.hpp"
#include "stvd/types.hpp"

namespace stvd::tetmesh {

/// A tetrahedral mesh. Vertex and tetrahedron indices are 0-based here;
/// `firstIndex` remembers the base of the file the mesh was read from, so
/// that vertex v is number v + firstIndex in that file and in every output
/// that names vertices.
struct TetMesh {
  std::vector<Vec3d> points;
  /// Corner indices of each tetrahedron, in TetGen's orientation: the
  /// signed volume det(p1 - p0, p2 - p0, p3 - p0) / 6 is positive (seen from
  /// p3, the corners p0 p1 p2 run counter-clockwise). See signedVolume().
  std::vector<std::array<VertexId, 4>> tets;
  /// Boundary triangles (from a .face file), possibly empty.
  std::vector<std::array<VertexId, 3>> faces;

  /// Per-point attributes, pointAttributeCount values per point, row-major.
  std::size_t pointAttributeCount = 0;
  std::vector<double> pointAttributes;
  /// Per-point boundary markers; empty when the file has none.
  std::vector<std::int64_t> pointMarkers;
  /// Per-tetrahedron attributes (TetGen's region attribute is the last one
  /// when the mesh was made with -A), tetAttributeCount per tetrahedron.
  std::size_t tetAttributeCount = 0;
  std::vector<double> tetAttributes;
  /// Per-face boundary markers; empty when the .face file has none.
  std::vector<std::int64_t> faceMarkers;

  /// 0 or 1: the number of the first vertex in the files.
  int firstIndex = 0;

  std::size_t vertexCount() const { return points.size(); }
  /// The number vertex v has in the input files.
  std::int64_t fileNumber(VertexId v) const { return static_cast<std::int64_t>(v) + firstIndex; }
};

/// Signed volume det(b - a, c - a, d - a) / 6.
double signedVolume(const Vec3d& a, const Vec3d& b, const Vec3d& c, const Vec3d& d);

/// How strict the geometric checks are.
struct TetMeshChecks {
  /// A tetrahedron whose |volume| is at most this times the cube of its
  /// longest edge is degenerate (flat). A regular tetrahedron has 0.118.
  double degenerateRelativeVolume = 1e-10;
};

/// Reads `base`.node, `base`.ele and, when it exists, `base`.face. `path`
/// may be the base name or any of the three files ("mesh.1.node" ->
/// "mesh.1"). Indices may start at 0 or 1 (the first point's number decides;
/// points must be numbered consecutively, and the .ele and .face files use
/// the same base). '#' starts a comment anywhere on a line; blank lines are
/// skipped. Second-order tetrahedra (10 nodes) keep their 4 corners.
/// Then validates as validateTetMesh does. Throws TetMeshError.
TetMesh readTetGenMesh(const std::string& path, const TetMeshChecks& checks = {});

/// The base name of a TetGen file set: "dir/mesh.1.ele" -> "dir/mesh.1";
/// a path without .node/.ele/.face stays as it is.
std::string tetGenBaseName(const std::string& path);

/// Throws TetMeshError, naming `fileForMessages` (the .ele file) and the
/// tetrahedron in the file's numbering, for: a corner out of range, a
/// repeated corner, a non-finite point coordinate (naming the .node file), a
/// degenerate (flat) tetrahedron, or an inverted one (negative signed
/// volume, against TetGen's orientation).
void validateTetMesh(const TetMesh& mesh, const std::string& nodeFile, const std::string& eleFile,
                     const TetMeshChecks& checks = {});

/// The tetrahedron containing p (boundary included, with a small relative
/// tolerance), or -1. Linear scan: meant for a handful of seed points.
std::int64_t findContainingTet(const TetMesh& mesh, const Vec3d& p);
/// The same over any points and tetrahedra; when `barycentric` is not null
/// it receives p's barycentric coordinates in the tetrahedron found.
std::int64_t findContainingTet(const std::vector<Vec3d>& points, const std::vector<std::array<VertexId, 4>>& tets,
                               const Vec3d& p, std::array<double, 4>* barycentric = nullptr);
/// The vertex nearest to p (Euclidean), or kNoVertex for an empty mesh.
VertexId nearestVertex(const TetMesh& mesh, const Vec3d& p);

}  // namespace stvd::tetmesh
