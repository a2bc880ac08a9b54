#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <utility>

#include "stvd/surface_io/cortical_surface_files.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"

namespace stvd::surface_io {
namespace {

std::string lowerExtension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos) return "";
  std::string e = path.substr(dot);
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

template <class T>
void putLittle(std::ostream& out, T value) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  const std::uint16_t one = 1;
  if (*reinterpret_cast<const unsigned char*>(&one) != 1)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  out.write(reinterpret_cast<const char*>(b), sizeof(T));
}

/// A coordinate in the mesh's own type: the value it was read from.
void putCoordinate(std::ostream& out, double x, ScalarType type) {
  switch (type) {
    case ScalarType::Int8: putLittle(out, static_cast<std::int8_t>(x)); return;
    case ScalarType::UInt8: putLittle(out, static_cast<std::uint8_t>(x)); return;
    case ScalarType::Int16: putLittle(out, static_cast<std::int16_t>(x)); return;
    case ScalarType::UInt16: putLittle(out, static_cast<std::uint16_t>(x)); return;
    case ScalarType::Int32: putLittle(out, static_cast<std::int32_t>(x)); return;
    case ScalarType::UInt32: putLittle(out, static_cast<std::uint32_t>(x)); return;
    case ScalarType::Float32: putLittle(out, static_cast<float>(x)); return;
    case ScalarType::Float64: putLittle(out, x); return;
  }
}

void writePly(std::ofstream& out, const SurfaceMesh& m, const std::vector<double>& d) {
  // Coordinates keep the input's type, so that every vertex is written back
  // exactly where it was read. Distances are float: the propagation
  // measures each edge in single precision, so more digits would only
  // repeat float rounding (sqrt(2) as 1.4142135381698608).
  const char* coordinate = plyTypeName(m.coordinateType);
  out << "ply\nformat binary_little_endian 1.0\ncomment stvd surface distance\n"
      << "element vertex " << m.points.size() << "\n"
      << "property " << coordinate << " x\nproperty " << coordinate << " y\nproperty " << coordinate
      << " z\nproperty float distance\n"
      << "element face " << m.faces.faceCount() << "\n"
      << "property list uchar int vertex_indices\nend_header\n";
  for (std::size_t v = 0; v < m.points.size(); ++v) {
    putCoordinate(out, m.points[v].x, m.coordinateType);
    putCoordinate(out, m.points[v].y, m.coordinateType);
    putCoordinate(out, m.points[v].z, m.coordinateType);
    putLittle(out, static_cast<float>(d[v]));
  }
  for (std::size_t f = 0; f < m.faces.faceCount(); ++f) {
    const std::uint32_t b = m.faces.faceStart[f], e = m.faces.faceStart[f + 1];
    if (e - b > 255) throw MeshFileError("a face with more than 255 vertices cannot be written to PLY");
    putLittle(out, static_cast<std::uint8_t>(e - b));
    for (std::uint32_t c = b; c < e; ++c) putLittle(out, static_cast<std::int32_t>(m.faces.faceVertex[c]));
  }
}

void writeVtk(std::ofstream& out, const SurfaceMesh& m, const std::vector<double>& d) {
  out << "# vtk DataFile Version 3.0\nstvd surface distance (unreached: -1)\nASCII\n"
      << "DATASET POLYDATA\nPOINTS " << m.points.size() << " double\n"
      << std::setprecision(17);
  for (const Vec3d& p : m.points) out << p.x << ' ' << p.y << ' ' << p.z << '\n';
  out << "POLYGONS " << m.faces.faceCount() << ' '
      << m.faces.faceCount() + m.faces.faceVertex.size() << '\n';
  for (std::size_t f = 0; f < m.faces.faceCount(); ++f) {
    out << m.faces.faceStart[f + 1] - m.faces.faceStart[f];
    for (std::uint32_t c = m.faces.faceStart[f]; c < m.faces.faceStart[f + 1]; ++c)
      out << ' ' << m.faces.faceVertex[c];
    out << '\n';
  }
  out << "POINT_DATA " << m.points.size() << "\nSCALARS distance double 1\nLOOKUP_TABLE default\n";
  for (const double x : d) out << (std::isfinite(x) ? x : -1.0) << '\n';
}

void writeCsv(std::ofstream& out, const std::vector<double>& d) {
  out << "vertex,distance\n" << std::setprecision(17);
  for (std::size_t v = 0; v < d.size(); ++v) {
    out << v << ',';
    if (std::isfinite(d[v])) out << d[v];
    else out << "inf";
    out << '\n';
  }
}

}  // namespace

void writeSurfaceDistances(const std::string& path, const std::string& formatPath,
                           const SurfaceMesh& mesh, const std::vector<double>& distance) {
  if (distance.size() != mesh.points.size())
    throw MeshFileError(path + ": " + std::to_string(distance.size()) + " distances for " +
                        std::to_string(mesh.points.size()) + " vertices");
  if (vertexValuesFormatOf(formatPath) != VertexValuesFormat::None) {
    // Unreached vertices are NaN: what Connectome Workbench, freeview and
    // nilearn leave uncoloured (an infinity would stretch their colour scales).
    std::vector<double> shown(distance);
    for (double& d : shown)
      if (!std::isfinite(d)) d = std::numeric_limits<double>::quiet_NaN();
    writeVertexValues(path, formatPath, mesh, shown, "geodesic distance");
    return;
  }
  const std::string e = lowerExtension(formatPath);
  if (e != ".ply" && e != ".vtk" && e != ".csv")
    throw MeshFileError(formatPath + ": unknown output format (expected .ply, .vtk, .csv, .shape.gii, .func.gii or FreeSurfer curv)");
  std::ofstream out(path, std::ios::binary);
  if (!out) throw MeshFileError(path + ": cannot create the file: " + std::strerror(errno));
  if (e == ".ply") writePly(out, mesh, distance);
  else if (e == ".vtk") writeVtk(out, mesh, distance);
  else writeCsv(out, distance);
  out.close();
  if (!out) throw MeshFileError(path + ": cannot write the file (disk full or file size limit?)");
}

}  // namespace stvd::surface_io
