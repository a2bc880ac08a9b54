#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "stvd/system/files/regular_file.hpp"
#include "stvd/surface_io/cortical_surface_files.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"

namespace stvd::surface_io {
namespace {

std::string lowerExtension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string e = path.substr(dot);
  for (char& c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

/// The whole file: a regular file only (a FIFO or a device such as
/// /dev/zero named like a mesh would block the reader or never end).
std::string readAll(const std::string& path) {
  try {
    return files::readRegularFile(path);
  } catch (const files::InputFileError& e) {
    throw MeshFileError(path + ": " + (e.problem() == "no such file" ? "cannot open the file: No such file or directory"
                                                                      : e.problem()));
  }
}

/// Splits into lines (LF or CRLF); `lines[i]` is line i + 1 of the file.
std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t start = 0;
  while (start <= text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(start, end - start);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(std::move(line));
    if (end == text.size()) break;
    start = end + 1;
  }
  return lines;
}

std::vector<std::string> tokens(const std::string& line) {
  std::vector<std::string> out;
  std::istringstream in(line);
  std::string t;
  while (in >> t) out.push_back(t);
  return out;
}

bool parseDouble(const std::string& t, double& x) {
  char* end = nullptr;
  x = std::strtod(t.c_str(), &end);
  return end != t.c_str() && *end == '\0' && std::isfinite(x);
}

bool parseLong(const std::string& t, long long& x) {
  char* end = nullptr;
  errno = 0;
  x = std::strtoll(t.c_str(), &end, 10);
  return end != t.c_str() && *end == '\0' && errno == 0;
}

std::string at(const std::string& path, std::size_t line) {
  return path + ": line " + std::to_string(line) + ": ";
}

void requireFaces(const std::string& path, const SurfaceMesh& m) {
  if (m.points.empty()) throw MeshFileError(path + ": the file has no vertices");
  if (m.faces.faceCount() == 0) throw MeshFileError(path + ": the file has no faces");
}

}  // namespace

bool isSurfaceMeshPath(const std::string& path) {
  const std::string e = lowerExtension(path);
  return e == ".obj" || e == ".off" || e == ".ply" || e == ".stl" || e == ".gii" || hasFreeSurferHemisphereName(path);
}

bool isSurfaceOutputPath(const std::string& path) {
  const std::string e = lowerExtension(path);
  return e == ".ply" || e == ".vtk" || e == ".csv" || vertexValuesFormatOf(path) != VertexValuesFormat::None;
}

SurfaceMesh readSurfaceMesh(const std::string& path) {
  const std::string e = lowerExtension(path);
  if (e == ".obj") return readObj(path);
  if (e == ".off") return readOff(path);
  if (e == ".ply") return readPly(path);
  if (e == ".stl") return readStl(path);
  if (e == ".gii") return readGiftiSurface(path);
  if (isFreeSurferSurfaceFile(path) || hasFreeSurferHemisphereName(path)) return readFreeSurferSurface(path);
  throw MeshFileError(path + ": unknown surface format (expected .obj, .off, .ply, .stl, .surf.gii or a FreeSurfer "
                             "surface such as lh.pial)");
}

// Wavefront OBJ: "v x y z [w]" and "f i i i ..." with i, i/t, i//n or i/t/n,
// 1-based or negative (relative to the vertices so far). Other statements
// (vt, vn, g, o, s, usemtl, mtllib, l, p) are ignored.
SurfaceMesh readObj(const std::string& path) {
  const std::vector<std::string> lines = splitLines(readAll(path));
  SurfaceMesh m;
  std::vector<VertexId> face;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const std::string& line = lines[i];
    const std::size_t hash = line.find('#');
    const std::vector<std::string> t = tokens(hash == std::string::npos ? line : line.substr(0, hash));
    if (t.empty()) continue;
    if (t[0] == "v") {
      double x, y, z;
      if (t.size() < 4 || !parseDouble(t[1], x) || !parseDouble(t[2], y) || !parseDouble(t[3], z))
        throw MeshFileError(at(path, i + 1) + "a vertex needs three finite coordinates");
      m.points.push_back({x, y, z});
    } else if (t[0] == "f") {
      face.clear();
      for (std::size_t k = 1; k < t.size(); ++k) {
        long long index;
        if (!parseLong(t[k].substr(0, t[k].find('/')), index) || index == 0)
          throw MeshFileError(at(path, i + 1) + "bad vertex index \"" + t[k] + "\"");
        const long long n = static_cast<long long>(m.points.size());
        const long long zeroBased = index > 0 ? index - 1 : n + index;
        if (zeroBased < 0 || zeroBased >= n)
          throw MeshFileError(at(path, i + 1) + "vertex index " + std::to_string(index) +
                              " refers to no vertex defined so far (" + std::to_string(n) + ")");
        face.push_back(static_cast<VertexId>(zeroBased));
      }
      if (face.size() < 3)
        throw MeshFileError(at(path, i + 1) + "a face needs at least 3 vertices");
      m.faces.add(face.begin(), face.end());
    }
  }
  requireFaces(path, m);
  return m;
}

// OFF: "OFF" (or COFF, NOFF, CNOFF; the extra per-vertex values are
// ignored), "nv nf ne", nv vertex lines, nf lines "n i_1 ... i_n [colour]".
SurfaceMesh readOff(const std::string& path) {
  const std::vector<std::string> lines = splitLines(readAll(path));
  // Meaningful tokens with their line numbers, one group per line.
  std::size_t next = 0;
  auto nextLine = [&](std::vector<std::string>& t) {
    while (next < lines.size()) {
      const std::string& line = lines[next++];
      const std::size_t hash = line.find('#');
      t = tokens(hash == std::string::npos ? line : line.substr(0, hash));
      if (!t.empty()) return true;
    }
    return false;
  };
  std::vector<std::string> t;
  if (!nextLine(t)) throw MeshFileError(path + ": the file is empty");
  const std::string& magic = t[0];
  if (magic.size() < 3 || magic.compare(magic.size() - 3, 3, "OFF") != 0 ||
      magic.find_first_not_of("STCN4") < magic.size() - 3)
    throw MeshFileError(at(path, next) + "not an OFF file (the first word is \"" + magic + "\")");
  if (magic.find('4') != std::string::npos)
    throw MeshFileError(at(path, next) + "4D OFF files are not supported");
  t.erase(t.begin());
  if (!t.empty() && t[0] == "BINARY")
    throw MeshFileError(at(path, next) + "binary OFF files are not supported");
  if (t.empty() && !nextLine(t)) throw MeshFileError(path + ": the counts line is missing");
  long long nv, nf;
  if (t.size() < 2 || !parseLong(t[0], nv) || !parseLong(t[1], nf) || nv < 0 || nf < 0)
    throw MeshFileError(at(path, next) + "expected the counts \"vertices faces edges\"");
  // Every vertex takes a line of its own: no more is reserved than the lines
  // left can hold, whatever the counts announce.
  const std::size_t linesLeft = lines.size() - std::min(next, lines.size());
  SurfaceMesh m;
  m.points.reserve(std::min(static_cast<std::size_t>(nv), linesLeft));
  for (long long v = 0; v < nv; ++v) {
    double x, y, z;
    if (!nextLine(t))
      throw MeshFileError(path + ": the file ends after " + std::to_string(v) + " of " +
                          std::to_string(nv) + " vertices");
    if (t.size() < 3 || !parseDouble(t[0], x) || !parseDouble(t[1], y) || !parseDouble(t[2], z))
      throw MeshFileError(at(path, next) + "vertex " + std::to_string(v) +
                          " needs three finite coordinates");
    m.points.push_back({x, y, z});
  }
  std::vector<VertexId> face;
  for (long long f = 0; f < nf; ++f) {
    if (!nextLine(t))
      throw MeshFileError(path + ": the file ends after " + std::to_string(f) + " of " +
                          std::to_string(nf) + " faces");
    long long count;
    if (!parseLong(t[0], count) || count < 3 || static_cast<long long>(t.size()) < count + 1)
      throw MeshFileError(at(path, next) + "face " + std::to_string(f) +
                          ": expected a vertex count of at least 3 and that many indices");
    face.clear();
    for (long long k = 1; k <= count; ++k) {
      long long index;
      if (!parseLong(t[k], index) || index < 0 || index >= nv)
        throw MeshFileError(at(path, next) + "face " + std::to_string(f) + ": vertex index \"" +
                            t[k] + "\" is not one of the " + std::to_string(nv) + " vertices");
      face.push_back(static_cast<VertexId>(index));
    }
    m.faces.add(face.begin(), face.end());
  }
  requireFaces(path, m);
  return m;
}

namespace {

using PlyType = ScalarType;

bool plyType(const std::string& name, PlyType& type) {
  static const std::pair<const char*, PlyType> names[] = {
      {"char", PlyType::Int8},     {"int8", PlyType::Int8},       {"uchar", PlyType::UInt8},
      {"uint8", PlyType::UInt8},   {"short", PlyType::Int16},     {"int16", PlyType::Int16},
      {"ushort", PlyType::UInt16}, {"uint16", PlyType::UInt16},   {"int", PlyType::Int32},
      {"int32", PlyType::Int32},   {"uint", PlyType::UInt32},     {"uint32", PlyType::UInt32},
      {"float", PlyType::Float32}, {"float32", PlyType::Float32}, {"double", PlyType::Float64},
      {"float64", PlyType::Float64}};
  for (const auto& [n, t] : names)
    if (name == n) {
      type = t;
      return true;
    }
  return false;
}

int plySize(PlyType t) {
  switch (t) {
    case PlyType::Int8: case PlyType::UInt8: return 1;
    case PlyType::Int16: case PlyType::UInt16: return 2;
    case PlyType::Int32: case PlyType::UInt32: case PlyType::Float32: return 4;
    case PlyType::Float64: return 8;
  }
  return 0;
}

struct PlyProperty {
  std::string name;
  bool isList = false;
  PlyType countType = PlyType::UInt8, type = PlyType::Float32;
};
struct PlyElement {
  std::string name;
  long long count = 0;
  std::vector<PlyProperty> properties;
};

/// Reads values of the body: binary (either byte order) or ASCII tokens.
class PlyBody {
 public:
  PlyBody(const std::string& path, const std::string& text, std::size_t start, int format)
      : path_(path), text_(text), pos_(start), format_(format) {}

  /// Bytes of the body not read yet.
  std::size_t remaining() const { return text_.size() - std::min(pos_, text_.size()); }

  double read(PlyType t, const std::string& where) {
    if (format_ == 0) return readAscii(t, where);
    const int n = plySize(t);
    if (pos_ + static_cast<std::size_t>(n) > text_.size())
      throw MeshFileError(path_ + ": " + where + ": the file ends early");
    unsigned char b[8];
    std::memcpy(b, text_.data() + pos_, n);
    pos_ += n;
    const bool little = format_ == 1;
    const std::uint16_t one = 1;
    const bool hostLittle = *reinterpret_cast<const unsigned char*>(&one) == 1;
    if (little != hostLittle) std::reverse(b, b + n);
    switch (t) {
      case PlyType::Int8: { std::int8_t v; std::memcpy(&v, b, 1); return v; }
      case PlyType::UInt8: return b[0];
      case PlyType::Int16: { std::int16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::UInt16: { std::uint16_t v; std::memcpy(&v, b, 2); return v; }
      case PlyType::Int32: { std::int32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::UInt32: { std::uint32_t v; std::memcpy(&v, b, 4); return v; }
      case PlyType::Float32: { float v; std::memcpy(&v, b, 4); return v; }
      case PlyType::Float64: { double v; std::memcpy(&v, b, 8); return v; }
    }
    return 0.0;
  }

 private:
  double readAscii(PlyType t, const std::string& where) {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    std::size_t end = pos_;
    while (end < text_.size() && !std::isspace(static_cast<unsigned char>(text_[end]))) ++end;
    if (end == pos_) throw MeshFileError(path_ + ": " + where + ": the file ends early");
    const std::string token = text_.substr(pos_, end - pos_);
    pos_ = end;
    double x;
    if (t == PlyType::Float32 || t == PlyType::Float64) {
      char* stop = nullptr;
      x = std::strtod(token.c_str(), &stop);
      if (*stop != '\0' || stop == token.c_str())
        throw MeshFileError(path_ + ": " + where + ": \"" + token + "\" is not a number");
    } else {
      long long v;
      if (!parseLong(token, v))
        throw MeshFileError(path_ + ": " + where + ": \"" + token + "\" is not an integer");
      x = static_cast<double>(v);
    }
    return x;
  }

  const std::string& path_;
  const std::string& text_;
  std::size_t pos_;
  int format_;  // 0 ascii, 1 binary little-endian, 2 binary big-endian
};

}  // namespace

// PLY 1.0, ascii / binary_little_endian / binary_big_endian. The element
// "vertex" needs properties x, y, z (any scalar type); "face" needs a list
// property vertex_indices (or vertex_index). Other elements and properties
// are read over and ignored.
SurfaceMesh readPly(const std::string& path) {
  const std::string text = readAll(path);
  const std::size_t headerEnd = text.find("end_header");
  if (text.compare(0, 3, "ply") != 0)
    throw MeshFileError(path + ": not a PLY file (it does not start with \"ply\")");
  if (headerEnd == std::string::npos) throw MeshFileError(path + ": the PLY header has no end_header");
  std::size_t bodyStart = text.find('\n', headerEnd);
  bodyStart = bodyStart == std::string::npos ? text.size() : bodyStart + 1;
  const std::vector<std::string> header = splitLines(text.substr(0, headerEnd));
  int format = -1;
  std::vector<PlyElement> elements;
  for (std::size_t i = 1; i < header.size(); ++i) {
    const std::vector<std::string> t = tokens(header[i]);
    if (t.empty() || t[0] == "comment" || t[0] == "obj_info") continue;
    if (t[0] == "format") {
      if (t.size() < 2) throw MeshFileError(at(path, i + 1) + "format without a name");
      if (t[1] == "ascii") format = 0;
      else if (t[1] == "binary_little_endian") format = 1;
      else if (t[1] == "binary_big_endian") format = 2;
      else throw MeshFileError(at(path, i + 1) + "unknown PLY format \"" + t[1] + "\"");
    } else if (t[0] == "element") {
      long long count;
      if (t.size() < 3 || !parseLong(t[2], count) || count < 0)
        throw MeshFileError(at(path, i + 1) + "expected \"element NAME COUNT\"");
      elements.push_back({t[1], count, {}});
    } else if (t[0] == "property") {
      if (elements.empty()) throw MeshFileError(at(path, i + 1) + "a property before any element");
      PlyProperty p;
      bool ok;
      if (t.size() >= 5 && t[1] == "list") {
        p.isList = true;
        ok = plyType(t[2], p.countType) && plyType(t[3], p.type);
        p.name = t[4];
      } else {
        ok = t.size() >= 3 && plyType(t[1], p.type);
        if (t.size() >= 3) p.name = t[2];
      }
      if (!ok) throw MeshFileError(at(path, i + 1) + "bad property \"" + header[i] + "\"");
      elements.back().properties.push_back(p);
    } else {
      throw MeshFileError(at(path, i + 1) + "unknown header line \"" + header[i] + "\"");
    }
  }
  if (format < 0) throw MeshFileError(path + ": the PLY header has no format line");

  SurfaceMesh m;
  PlyBody body(path, text, bodyStart, format);
  bool sawVertices = false;
  std::vector<VertexId> face;
  for (const PlyElement& e : elements) {
    const bool isVertex = e.name == "vertex", isFace = e.name == "face";
    int xyz[3] = {-1, -1, -1}, indices = -1;
    for (std::size_t p = 0; p < e.properties.size(); ++p) {
      const PlyProperty& q = e.properties[p];
      if (isVertex && !q.isList && (q.name == "x" || q.name == "y" || q.name == "z"))
        xyz[q.name[0] - 'x'] = static_cast<int>(p);
      if (isFace && q.isList && (q.name == "vertex_indices" || q.name == "vertex_index"))
        indices = static_cast<int>(p);
    }
    if (isVertex && (xyz[0] < 0 || xyz[1] < 0 || xyz[2] < 0))
      throw MeshFileError(path + ": the vertex element lacks one of the properties x, y, z");
    if (isVertex) {
      const PlyType x = e.properties[xyz[0]].type;
      m.coordinateType = x == e.properties[xyz[1]].type && x == e.properties[xyz[2]].type ? x : PlyType::Float64;
    }
    if (isFace && indices < 0)
      throw MeshFileError(path + ": the face element has no list property vertex_indices");
    if (isFace && !sawVertices)
      throw MeshFileError(path + ": the face element comes before the vertex element");
    // A record takes at least one byte per value in binary (one character
    // and a separator in ASCII): a count the rest of the file cannot hold is
    // refused here, and a record without properties holds nothing to read.
    if (e.properties.empty()) continue;
    std::size_t recordBytes = 0;
    for (const PlyProperty& q : e.properties)
      recordBytes += format == 0 ? 1 : static_cast<std::size_t>(plySize(q.isList ? q.countType : q.type));
    if (static_cast<unsigned long long>(e.count) > body.remaining() / recordBytes)
      throw MeshFileError(path + ": the header announces " + std::to_string(e.count) + " " + e.name +
                          " records, more than the " + std::to_string(body.remaining()) +
                          " bytes left in the file can hold");
    for (long long i = 0; i < e.count; ++i) {
      const std::string where = e.name + " " + std::to_string(i);
      double coordinate[3] = {0, 0, 0};
      face.clear();
      for (std::size_t p = 0; p < e.properties.size(); ++p) {
        const PlyProperty& q = e.properties[p];
        if (!q.isList) {
          const double x = body.read(q.type, where);
          for (int c = 0; c < 3; ++c)
            if (static_cast<int>(p) == xyz[c]) coordinate[c] = x;
          continue;
        }
        const double count = body.read(q.countType, where);
        if (!(count >= 0) || count > 1e6)
          throw MeshFileError(path + ": " + where + ": bad list length " + std::to_string(count));
        for (long long k = 0; k < static_cast<long long>(count); ++k) {
          const double x = body.read(q.type, where);
          if (static_cast<int>(p) != indices) continue;
          if (!(x >= 0) || x >= static_cast<double>(m.points.size()) || x != std::floor(x))
            throw MeshFileError(path + ": " + where + ": vertex index " +
                                (x == std::floor(x) && std::abs(x) < 1e15
                                     ? std::to_string(static_cast<long long>(x))
                                     : std::to_string(x)) +
                                " is not one of the " + std::to_string(m.points.size()) +
                                " vertices");
          face.push_back(static_cast<VertexId>(x));
        }
      }
      if (isVertex) {
        for (const double c : coordinate)
          if (!std::isfinite(c))
            throw MeshFileError(path + ": " + where + ": a coordinate is not a finite number");
        m.points.push_back({coordinate[0], coordinate[1], coordinate[2]});
      }
      if (isFace) {
        if (face.size() < 3)
          throw MeshFileError(path + ": " + where + ": a face needs at least 3 vertices");
        m.faces.add(face.begin(), face.end());
      }
    }
    sawVertices = sawVertices || isVertex;
  }
  requireFaces(path, m);
  return m;
}

const char* plyTypeName(ScalarType type) {
  switch (type) {
    case ScalarType::Int8: return "char";
    case ScalarType::UInt8: return "uchar";
    case ScalarType::Int16: return "short";
    case ScalarType::UInt16: return "ushort";
    case ScalarType::Int32: return "int";
    case ScalarType::UInt32: return "uint";
    case ScalarType::Float32: return "float";
    case ScalarType::Float64: return "double";
  }
  return "double";
}

namespace {

/// Welds STL corners into vertices by exact coordinates.
class StlWelder {
 public:
  explicit StlWelder(SurfaceMesh& mesh) : mesh_(mesh) {}
  void facet(const Vec3d (&corner)[3]) {
    VertexId v[3];
    for (int c = 0; c < 3; ++c) {
      const auto [it, inserted] = index_.emplace(std::array<double, 3>{corner[c].x, corner[c].y, corner[c].z},
                                                 static_cast<VertexId>(mesh_.points.size()));
      if (inserted) mesh_.points.push_back(corner[c]);
      else ++mesh_.weldedVertices;
      v[c] = it->second;
    }
    if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) {
      ++mesh_.degenerateFacets;
      return;
    }
    mesh_.faces.add(v, v + 3);
  }

 private:
  SurfaceMesh& mesh_;
  std::map<std::array<double, 3>, VertexId> index_;
};

}  // namespace

SurfaceMesh readStl(const std::string& path) {
  const std::string bytes = readAll(path);
  SurfaceMesh m;
  StlWelder welder(m);
  std::uint32_t count = 0;
  if (bytes.size() >= 84) std::memcpy(&count, bytes.data() + 80, 4);  // little-endian on every target
  if (bytes.size() >= 84 && bytes.size() == 84 + 50ull * count) {
    m.coordinateType = ScalarType::Float32;
    for (std::uint32_t f = 0; f < count; ++f) {
      const char* at = bytes.data() + 84 + 50ull * f + 12;  // after the facet normal
      Vec3d corner[3];
      for (int c = 0; c < 3; ++c) {
        float xyz[3];
        std::memcpy(xyz, at + 12 * c, 12);
        if (!std::isfinite(xyz[0]) || !std::isfinite(xyz[1]) || !std::isfinite(xyz[2]))
          throw MeshFileError(path + ": facet " + std::to_string(f) + ": a coordinate is not a finite number");
        corner[c] = {xyz[0], xyz[1], xyz[2]};
      }
      welder.facet(corner);
    }
  } else {
    const std::vector<std::string> lines = splitLines(bytes);
    std::size_t first = 0;
    while (first < lines.size() && tokens(lines[first]).empty()) ++first;
    if (first == lines.size() || tokens(lines[first])[0] != "solid")
      throw MeshFileError(path + ": not an STL file (neither \"solid\" text nor binary of " +
                          std::to_string(bytes.size()) + " bytes, which " +
                          (bytes.size() >= 84 ? std::to_string(count) + " triangles would make " +
                                                    std::to_string(84 + 50ull * count)
                                              : std::string("a binary header needs at least 84")) +
                          ")");
    Vec3d corner[3];
    int corners = -1;  // -1: outside a facet
    bool ended = false;
    for (std::size_t i = first + 1; i < lines.size() && !ended; ++i) {
      const std::vector<std::string> t = tokens(lines[i]);
      if (t.empty()) continue;
      if (t[0] == "facet") {
        if (corners >= 0) throw MeshFileError(at(path, i + 1) + "a facet inside a facet");
        corners = 0;
      } else if (t[0] == "vertex") {
        double x, y, z;
        if (corners < 0 || corners >= 3)
          throw MeshFileError(at(path, i + 1) + "a vertex outside a facet, or a fourth one");
        if (t.size() != 4 || !parseDouble(t[1], x) || !parseDouble(t[2], y) || !parseDouble(t[3], z))
          throw MeshFileError(at(path, i + 1) + "a vertex needs three finite coordinates");
        corner[corners++] = {x, y, z};
      } else if (t[0] == "endfacet") {
        if (corners != 3) throw MeshFileError(at(path, i + 1) + "a facet needs exactly 3 vertices");
        welder.facet(corner);
        corners = -1;
      } else if (t[0] == "endsolid") {
        ended = true;
      } else if (t[0] != "outer" && t[0] != "endloop") {
        throw MeshFileError(at(path, i + 1) + "unknown STL keyword \"" + t[0] + "\"");
      }
    }
    if (corners >= 0) throw MeshFileError(path + ": the file ends inside a facet");
  }
  requireFaces(path, m);
  return m;
}

}  // namespace stvd::surface_io

namespace stvd::surface_io {

std::vector<std::vector<double>> readVertexTable(const std::string& path, std::size_t columns,
                                                 std::size_t rows, const std::string& rowKind) {
  const std::string plural = rowKind == "vertex" ? "vertices" : rowKind + "s";
  const std::vector<std::string> lines = splitLines(readAll(path));
  std::vector<std::vector<double>> table;
  bool first = true;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    std::string line = lines[i];
    std::replace(line.begin(), line.end(), ',', ' ');
    const std::vector<std::string> t = tokens(line);
    if (t.empty() || t[0][0] == '#') continue;
    std::vector<double> row;
    bool numeric = true;
    for (const std::string& x : t) {
      double value;
      if (!parseDouble(x, value)) {
        numeric = false;
        break;
      }
      row.push_back(value);
    }
    if (!numeric && first) {  // a header
      first = false;
      continue;
    }
    first = false;
    if (!numeric || row.size() != columns)
      throw MeshFileError(at(path, i + 1) + "expected " + std::to_string(columns) +
                          " finite numbers (the values of " + rowKind + " " + std::to_string(table.size()) +
                          ")");
    table.push_back(std::move(row));
  }
  if (table.size() != rows)
    throw MeshFileError(path + ": " + std::to_string(table.size()) + " rows for " +
                        std::to_string(rows) + " " + plural);
  return table;
}

}  // namespace stvd::surface_io
