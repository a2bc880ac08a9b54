// Writers for tetrahedral meshes with per-vertex values.
#include "stvd/tetmesh/tet_mesh_writers.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <fstream>
#include <stdexcept>

namespace stvd::tetmesh {
namespace {

constexpr int kVtkTetra = 10;

std::string lowerExtension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string e = path.substr(dot);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

/// %.17g round-trips a double; nan and inf spelled the same on every C library.
void putNumber(std::ostream& out, double x) {
  if (std::isnan(x)) {
    out << "nan";
  } else if (std::isinf(x)) {
    out << (x > 0 ? "inf" : "-inf");
  } else {
    char text[32];
    std::snprintf(text, sizeof text, "%.17g", x);
    out << text;
  }
}

std::ofstream openForWriting(const std::string& path) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw TetMeshError(path + ": cannot open for writing");
  return out;
}

void finish(std::ofstream& out, const std::string& path) {
  out.flush();
  if (!out) throw TetMeshError(path + ": write error (disk full?)");
  out.close();
  if (out.fail()) throw TetMeshError(path + ": write error on close");
}

void checkFields(const TetMesh& mesh, const std::vector<VertexField>& fields) {
  for (const VertexField& f : fields)
    if (f.values.size() != mesh.vertexCount())
      throw std::invalid_argument("field '" + f.name + "' has " + std::to_string(f.values.size()) +
                                  " values for " + std::to_string(mesh.vertexCount()) + " vertices");
}

}  // namespace

bool outputFormatOf(const std::string& path, TetMeshOutputFormat& format) {
  const std::string e = lowerExtension(path);
  if (e == ".vtk") format = TetMeshOutputFormat::VtkLegacy;
  else if (e == ".vtu") format = TetMeshOutputFormat::Vtu;
  else if (e == ".csv") format = TetMeshOutputFormat::Csv;
  else return false;
  return true;
}

void writeVtkLegacy(const std::string& path, const TetMesh& mesh, const std::vector<VertexField>& fields) {
  checkFields(mesh, fields);
  std::ofstream out = openForWriting(path);
  const std::size_t n = mesh.vertexCount(), m = mesh.tets.size();
  out << "# vtk DataFile Version 3.0\nstvd tetrahedral mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  out << "POINTS " << n << " double\n";
  for (const Vec3d& p : mesh.points) {
    putNumber(out, p.x);
    out << ' ';
    putNumber(out, p.y);
    out << ' ';
    putNumber(out, p.z);
    out << '\n';
  }
  out << "CELLS " << m << ' ' << 5 * m << '\n';
  for (const auto& t : mesh.tets) out << "4 " << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
  out << "CELL_TYPES " << m << '\n';
  for (std::size_t i = 0; i < m; ++i) out << kVtkTetra << '\n';
  out << "POINT_DATA " << n << '\n';
  for (const VertexField& f : fields) {
    out << "SCALARS " << f.name << " double 1\nLOOKUP_TABLE default\n";
    for (double x : f.values) {
      putNumber(out, x);
      out << '\n';
    }
  }
  out << "SCALARS vertex_number long 1\nLOOKUP_TABLE default\n";
  for (std::size_t v = 0; v < n; ++v) out << mesh.fileNumber(static_cast<VertexId>(v)) << '\n';
  finish(out, path);
}

void writeVtu(const std::string& path, const TetMesh& mesh, const std::vector<VertexField>& fields) {
  checkFields(mesh, fields);
  std::ofstream out = openForWriting(path);
  const std::size_t n = mesh.vertexCount(), m = mesh.tets.size();
  out << "<?xml version=\"1.0\"?>\n"
         "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
         "  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << m << "\">\n";
  out << "      <PointData" << (fields.empty() ? "" : " Scalars=\"" + fields.front().name + "\"") << ">\n";
  for (const VertexField& f : fields) {
    out << "        <DataArray type=\"Float64\" Name=\"" << f.name << "\" format=\"ascii\">\n";
    for (double x : f.values) {
      putNumber(out, x);
      out << '\n';
    }
    out << "        </DataArray>\n";
  }
  out << "        <DataArray type=\"Int64\" Name=\"vertex_number\" format=\"ascii\">\n";
  for (std::size_t v = 0; v < n; ++v) out << mesh.fileNumber(static_cast<VertexId>(v)) << '\n';
  out << "        </DataArray>\n      </PointData>\n";
  out << "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const Vec3d& p : mesh.points) {
    putNumber(out, p.x);
    out << ' ';
    putNumber(out, p.y);
    out << ' ';
    putNumber(out, p.z);
    out << '\n';
  }
  out << "        </DataArray>\n      </Points>\n      <Cells>\n";
  out << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& t : mesh.tets) out << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
  out << "        </DataArray>\n        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 1; i <= m; ++i) out << 4 * i << '\n';
  out << "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < m; ++i) out << kVtkTetra << '\n';
  out << "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  finish(out, path);
}

void writeCsv(const std::string& path, const TetMesh& mesh, const std::vector<VertexField>& fields) {
  checkFields(mesh, fields);
  std::ofstream out = openForWriting(path);
  out << "vertex";
  for (const VertexField& f : fields) out << ',' << f.name;
  out << '\n';
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    out << mesh.fileNumber(static_cast<VertexId>(v));
    for (const VertexField& f : fields) {
      out << ',';
      putNumber(out, f.values[v]);
    }
    out << '\n';
  }
  finish(out, path);
}

void writeTetGenMesh(const std::string& base, const TetMesh& mesh) {
  const std::int64_t first = mesh.firstIndex;
  {
    const std::string path = base + ".node";
    std::ofstream out = openForWriting(path);
    const bool markers = !mesh.pointMarkers.empty();
    out << "# points, dimension, attributes, boundary markers\n"
        << mesh.vertexCount() << " 3 " << mesh.pointAttributeCount << ' ' << (markers ? 1 : 0) << '\n';
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
      out << first + static_cast<std::int64_t>(v);
      for (double x : {mesh.points[v].x, mesh.points[v].y, mesh.points[v].z}) {
        out << ' ';
        putNumber(out, x);
      }
      for (std::size_t a = 0; a < mesh.pointAttributeCount; ++a) {
        out << ' ';
        putNumber(out, mesh.pointAttributes[v * mesh.pointAttributeCount + a]);
      }
      if (markers) out << ' ' << mesh.pointMarkers[v];
      out << '\n';
    }
    finish(out, path);
  }
  {
    const std::string path = base + ".ele";
    std::ofstream out = openForWriting(path);
    out << "# tetrahedra, nodes per tetrahedron, attributes\n"
        << mesh.tets.size() << " 4 " << mesh.tetAttributeCount << '\n';
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      out << first + static_cast<std::int64_t>(t);
      for (VertexId c : mesh.tets[t]) out << ' ' << first + c;
      for (std::size_t a = 0; a < mesh.tetAttributeCount; ++a) {
        out << ' ';
        putNumber(out, mesh.tetAttributes[t * mesh.tetAttributeCount + a]);
      }
      out << '\n';
    }
    finish(out, path);
  }
  if (!mesh.faces.empty()) {
    const std::string path = base + ".face";
    std::ofstream out = openForWriting(path);
    const bool markers = !mesh.faceMarkers.empty();
    out << "# faces, boundary markers\n" << mesh.faces.size() << ' ' << (markers ? 1 : 0) << '\n';
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) {
      out << first + static_cast<std::int64_t>(f);
      for (VertexId c : mesh.faces[f]) out << ' ' << first + c;
      if (markers) out << ' ' << mesh.faceMarkers[f];
      out << '\n';
    }
    finish(out, path);
  }
}

void writeTetMeshOutput(const std::string& path, TetMeshOutputFormat format, const TetMesh& mesh,
                        const std::vector<VertexField>& fields) {
  switch (format) {
    case TetMeshOutputFormat::VtkLegacy: return writeVtkLegacy(path, mesh, fields);
    case TetMeshOutputFormat::Vtu: return writeVtu(path, mesh, fields);
    case TetMeshOutputFormat::Csv: return writeCsv(path, mesh, fields);
  }
}

}  // namespace stvd::tetmesh
