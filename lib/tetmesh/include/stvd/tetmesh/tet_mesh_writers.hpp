// Writers of a tetrahedral mesh with per-vertex values: legacy VTK (.vtk),
// VTK XML unstructured grid (.vtu), both loadable in ParaView, and a .csv
// table of (vertex number, value).
#pragma once

#include <string>
#include <vector>

#include "stvd/tetmesh/tet_mesh.hpp"

namespace stvd::tetmesh {

/// A named value per vertex, in the mesh's vertex order.
struct VertexField {
  std::string name;
  std::vector<double> values;
};

enum class TetMeshOutputFormat { VtkLegacy, Vtu, Csv };

/// The format an output path asks for by its extension (.vtk, .vtu, .csv,
/// any case); false when it is none of them.
bool outputFormatOf(const std::string& path, TetMeshOutputFormat& format);

/// Writes the mesh (points, tetrahedra as VTK_TETRA cells) and the fields
/// as point data. Every field gets a double array; a second array
/// "vertex_number" holds each vertex's number in the input files. VTK
/// formats cannot carry infinity portably: the caller replaces unreachable
/// values first. Throws TetMeshError naming `path` when writing fails.
void writeVtkLegacy(const std::string& path, const TetMesh& mesh, const std::vector<VertexField>& fields);
void writeVtu(const std::string& path, const TetMesh& mesh, const std::vector<VertexField>& fields);
/// Header "vertex,<field names>", then one line per vertex: its number in
/// the input files, then its values with 17 significant digits ("nan" and
/// "inf" as such).
void writeCsv(const std::string& path, const TetMesh& mesh, const std::vector<VertexField>& fields);

/// Writes `base`.node, `base`.ele and, when the mesh has faces, `base`.face
/// in TetGen's format, numbered from mesh.firstIndex, with all attributes
/// and markers; readTetGenMesh reads them back exactly (17 significant
/// digits). Throws TetMeshError naming the file when writing fails.
void writeTetGenMesh(const std::string& base, const TetMesh& mesh);

/// Dispatches on the format.
void writeTetMeshOutput(const std::string& path, TetMeshOutputFormat format, const TetMesh& mesh,
                        const std::vector<VertexField>& fields);

}  // namespace stvd::tetmesh
