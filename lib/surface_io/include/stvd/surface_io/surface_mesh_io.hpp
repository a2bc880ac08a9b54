// Reading polygon surfaces from .obj, .off and .ply (ASCII and binary
// little/big-endian), and writing a per-vertex distance as .ply, .vtk
// (legacy POLYDATA) or .csv (GIfTI and FreeSurfer: cortical_surface_files.hpp). See
// docs/surfaces.md for what each reader accepts.
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <vector>

#include "stvd/errors.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/types.hpp"

namespace stvd::surface_io {

/// The scalar type a file stores coordinates in (PLY's types).
enum class ScalarType { Int8, UInt8, Int16, UInt16, Int32, UInt32, Float32, Float64 };
/// PLY's name of the type: "char", "uchar", ..., "float", "double".
const char* plyTypeName(ScalarType type);

/// The space a surface's coordinates are in, as its file states it, and
/// the transform to another space when the file gives one.
struct SurfaceCoordinateSystem {
  /// "tkr-RAS" or "scanner RAS" (FreeSurfer), a GIfTI DataSpace
  /// ("NIFTI_XFORM_TALAIRACH", ...); empty when the file says nothing.
  std::string space;
  /// Where `transform` leads ("scanner RAS", a GIfTI TransformedSpace).
  std::string transformedSpace;
  bool hasTransform = false;
  /// Row-major 4 x 4 affine from `space` to `transformedSpace`.
  std::array<double, 16> transform{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
};

struct SurfaceMesh {
  std::vector<Vec3d> points;  // in file order: vertex i is the i-th vertex of the file
  PolygonList faces;          // polygons as given (not triangulated)
  /// The type the file held the coordinates in: PLY's declared type of x,
  /// y and z (Float64 when they differ), Float32 for binary STL, Float64
  /// for the text formats. The PLY writer keeps it, so vertices are written
  /// back exactly.
  ScalarType coordinateType = ScalarType::Float64;
  /// STL only: the facets' corners that coincided exactly with an earlier
  /// corner and became one vertex with it, and the facets left out because
  /// two of their corners coincided.
  std::size_t weldedVertices = 0;
  std::size_t degenerateFacets = 0;
  /// GIfTI and FreeSurfer surfaces: the coordinates' space (the
  /// coordinates are kept as stored), and the anatomical structure
  /// (GIfTI's AnatomicalStructurePrimary; CortexLeft/CortexRight for a
  /// FreeSurfer file named lh.* / rh.*), written into GIfTI outputs.
  SurfaceCoordinateSystem coordinates;
  std::string anatomicalStructure;
  /// The format read: "obj", "off", "ply", "stl", "gifti", "freesurfer".
  std::string format;
};

/// True when the path ends in .obj, .off, .ply, .stl or .gii (any letter
/// case), or is named like a FreeSurfer hemisphere file (lh.*, rh.*).
bool isSurfaceMeshPath(const std::string& path);

/// Reads by the extension (GIfTI for .gii); a FreeSurfer surface by its
/// magic number (any name). Throws MeshFileError.
SurfaceMesh readSurfaceMesh(const std::string& path);
SurfaceMesh readObj(const std::string& path);
SurfaceMesh readOff(const std::string& path);
SurfaceMesh readPly(const std::string& path);
/// STL, ASCII ("solid ... facet ... vertex x y z ... endsolid") or binary
/// (80-byte header, triangle count, 50 bytes per triangle; recognised by
/// its exact size, also when the header starts with "solid"). STL lists
/// three corners per facet; corners with exactly the same coordinates are
/// welded into one vertex (counted in weldedVertices), in order of first
/// appearance, and facets with two equal corners are left out.
SurfaceMesh readStl(const std::string& path);

/// True when the path ends in .ply, .vtk, .csv or .gii (but not .surf.gii
/// or .label.gii), or .curv, or is a FreeSurfer hemisphere name (lh.*,
/// rh.*: a curv file).
bool isSurfaceOutputPath(const std::string& path);

/// Writes the mesh and one distance per vertex to `path` in the format of
/// `formatPath`'s extension (the two differ when the caller stages the file
/// under a temporary name):
///  .ply  binary little-endian PLY: x y z in the mesh's coordinateType
///        (exactly the input's values), distance (float: the precision the
///        propagation measures edges in); faces
///  .vtk  legacy ASCII POLYDATA, POINT_DATA SCALARS distance double
///  .csv  "vertex,distance" then one row per vertex, vertices from 0
///  .gii  GIfTI shape/func file, .curv or lh.* / rh.*: FreeSurfer curv
///        (cortical_surface_files.hpp: writeVertexValues)
/// A vertex that was not reached has distance +inf in .ply and .csv ("inf"),
/// -1 in .vtk (legacy VTK readers do not parse "inf") and NaN in GIfTI and
/// curv files (what Connectome Workbench, freeview and nilearn leave
/// uncoloured). Throws
/// MeshFileError when the file cannot be written.
void writeSurfaceDistances(const std::string& path, const std::string& formatPath,
                           const SurfaceMesh& mesh, const std::vector<double>& distance);

}  // namespace stvd::surface_io

namespace stvd::surface_io {

/// A per-vertex table in a text file: one row per vertex in vertex order,
/// `columns` numbers per row separated by spaces, tabs or commas. Empty
/// lines and lines starting with '#' are skipped, and so is a first row
/// that is not numeric (a header). Throws MeshFileError naming the file and
/// line for a bad row, or when the row count differs from `rows`. `rowKind`
/// names what a row describes in messages ("vertex", "face").
std::vector<std::vector<double>> readVertexTable(const std::string& path, std::size_t columns,
                                                 std::size_t rows,
                                                 const std::string& rowKind = "vertex");

}  // namespace stvd::surface_io
