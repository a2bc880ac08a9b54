// FreeSurfer's files: binary triangle surfaces with their volume geometry,
// curv files, .mgh/.mgz volumes of per-vertex values, annotations and
// label files. All binary numbers are big-endian.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>

#include "encoded_data.hpp"
#include "freesurfer_files.hpp"
#include "stvd/surface_io/cortical_surface_files.hpp"
#include "stvd/system/files/regular_file.hpp"

namespace stvd::surface_io::detail {
namespace {

/// Reads big-endian numbers from a file's bytes, failing with the file's
/// name when they end.
class BigEndianReader {
 public:
  BigEndianReader(const std::string& bytes, const std::string& path, std::size_t at = 0)
      : b_(bytes), path_(path), at_(at) {}
  std::size_t left() const { return b_.size() - at_; }
  std::size_t at() const { return at_; }
  void need(std::size_t n, const std::string& what) const {
    if (left() < n) throw MeshFileError(path_ + ": the file ends in " + what);
  }
  std::int32_t int32(const std::string& what) {
    need(4, what);
    at_ += 4;
    return loadNumber<std::int32_t>(b_.data() + at_ - 4, true);
  }
  std::int16_t int16(const std::string& what) {
    need(2, what);
    at_ += 2;
    return loadNumber<std::int16_t>(b_.data() + at_ - 2, true);
  }
  float float32(const std::string& what) {
    need(4, what);
    at_ += 4;
    return loadNumber<float>(b_.data() + at_ - 4, true);
  }
  std::uint32_t int24(const std::string& what) {
    need(3, what);
    const auto* p = reinterpret_cast<const unsigned char*>(b_.data() + at_);
    at_ += 3;
    return (std::uint32_t(p[0]) << 16) | (std::uint32_t(p[1]) << 8) | p[2];
  }
  std::string text(std::size_t n, const std::string& what) {
    need(n, what);
    at_ += n;
    return b_.substr(at_ - n, n);
  }
  const char* here() const { return b_.data() + at_; }
  void skip(std::size_t n) { at_ += n; }

 private:
  const std::string& b_;
  const std::string& path_;
  std::size_t at_;
};

constexpr std::uint32_t kTriangleMagic = 0xFFFFFE, kQuadMagic = 0xFFFFFF, kNewQuadMagic = 0xFFFFFD;
constexpr std::uint32_t kNewCurvMagic = 0xFFFFFF;
constexpr std::int32_t kTagOldUseRealRas = 2, kTagOldSurfaceGeometry = 20;

std::string baseName(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// Affine 4 x 4 (row-major) inverse of a matrix whose last row is 0 0 0 1.
std::array<double, 16> inverseAffine(const std::array<double, 16>& m) {
  const double a = m[0], b = m[1], c = m[2], d = m[4], e = m[5], f = m[6], g = m[8], h = m[9], i = m[10];
  const double det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g);
  std::array<double, 16> r{};
  r[0] = (e * i - f * h) / det;
  r[1] = (c * h - b * i) / det;
  r[2] = (b * f - c * e) / det;
  r[4] = (f * g - d * i) / det;
  r[5] = (a * i - c * g) / det;
  r[6] = (c * d - a * f) / det;
  r[8] = (d * h - e * g) / det;
  r[9] = (b * g - a * h) / det;
  r[10] = (a * e - b * d) / det;
  for (int row = 0; row < 3; ++row)
    r[4 * row + 3] = -(r[4 * row] * m[3] + r[4 * row + 1] * m[7] + r[4 * row + 2] * m[11]);
  r[15] = 1.0;
  return r;
}

std::array<double, 16> multiply(const std::array<double, 16>& x, const std::array<double, 16>& y) {
  std::array<double, 16> r{};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) r[4 * i + j] += x[4 * i + k] * y[4 * k + j];
  return r;
}

/// The volume geometry's text block ("valid = 1", "filename = ...",
/// "volume = W H D", "voxelsize = ...", "xras = ...", "yras", "zras",
/// "cras") into the transform from tkr-RAS to scanner RAS:
/// vox2ras(scanner) * inverse(vox2ras(tkr)), FreeSurfer's own matrices of
/// the volume the surface was made on. For a conformed volume (LIA axes)
/// this is the translation by c_ras.
bool volumeGeometryTransform(const std::string& block, std::array<double, 16>& transform) {
  std::istringstream in(block);
  std::string line;
  std::map<std::string, std::vector<double>> numbers;
  bool valid = false;
  for (const char* key : {"valid", "filename", "volume", "voxelsize", "xras", "yras", "zras", "cras"}) {
    if (!std::getline(in, line)) return false;
    const std::size_t eq = line.find('=');
    if (eq == std::string::npos) return false;
    std::string name = line.substr(0, eq);
    name.erase(std::remove_if(name.begin(), name.end(), [](char c) { return c == ' ' || c == '\t'; }), name.end());
    if (name != key) return false;
    const std::string value = line.substr(eq + 1);
    if (name == "valid") valid = std::atoi(value.c_str()) == 1;
    if (name == "valid" || name == "filename") continue;
    std::istringstream v(value);
    double x;
    while (numbers[name].size() < 3 && v >> x) numbers[name].push_back(x);
    if (numbers[name].size() != 3 || !std::isfinite(numbers[name][0] + numbers[name][1] + numbers[name][2])) return false;
  }
  if (!valid) return false;
  const auto& dim = numbers["volume"];
  const auto& size = numbers["voxelsize"];
  const auto& xr = numbers["xras"];
  const auto& yr = numbers["yras"];
  const auto& zr = numbers["zras"];
  const auto& c = numbers["cras"];
  if (size[0] <= 0 || size[1] <= 0 || size[2] <= 0) return false;
  std::array<double, 16> scanner{};
  const std::array<const std::vector<double>*, 3> axes{&xr, &yr, &zr};
  for (int row = 0; row < 3; ++row) {
    double centre = 0.0;
    for (int col = 0; col < 3; ++col) {
      scanner[4 * row + col] = (*axes[col])[row] * size[col];
      centre += scanner[4 * row + col] * dim[col] / 2.0;
    }
    scanner[4 * row + 3] = c[row] - centre;
  }
  scanner[15] = 1.0;
  // MRIxfmCRS2XYZtkreg: the same voxels with LIA axes centred on 0.
  const std::array<double, 16> tkr{-size[0], 0, 0, size[0] * dim[0] / 2.0,  //
                                   0, 0, size[2], -size[2] * dim[2] / 2.0,  //
                                   0, -size[1], 0, size[1] * dim[1] / 2.0,  //
                                   0, 0, 0, 1};
  transform = multiply(scanner, inverseAffine(tkr));
  return true;
}

}  // namespace

std::string readFileBytes(const std::string& path) {
  try {
    return files::readRegularFile(path);
  } catch (const files::InputFileError& e) {
    throw MeshFileError(path + ": " + (e.problem() == "no such file" ? "cannot open the file: No such file or directory"
                                                                      : e.problem()));
  }
}

std::vector<double> readCurv(const std::string& path, const std::string& bytes, std::size_t vertexCount) {
  BigEndianReader r(bytes, path);
  const std::uint32_t magic = r.int24("the magic number");
  std::vector<double> values;
  if (magic == kNewCurvMagic) {
    const std::int32_t n = r.int32("the vertex count"), faces = r.int32("the face count"),
                       perVertex = r.int32("the values per vertex");
    (void)faces;
    if (perVertex != 1)
      throw MeshFileError(path + ": a curv file with " + std::to_string(perVertex) + " values per vertex (1 expected)");
    if (n < 0 || static_cast<std::size_t>(n) != vertexCount)
      throw MeshFileError(path + ": " + std::to_string(n) + " values for a surface of " + std::to_string(vertexCount) +
                          " vertices");
    r.need(4 * static_cast<std::size_t>(n), "the values");
    values.resize(static_cast<std::size_t>(n));
    for (auto& v : values) v = r.float32("the values");
  } else {
    // The old format: 3-byte vertex and face counts, int16 values / 100.
    const std::uint32_t n = magic;
    r.int24("the face count");
    if (n != vertexCount)
      throw MeshFileError(path + ": " + std::to_string(n) + " values for a surface of " + std::to_string(vertexCount) +
                          " vertices (old-format curv file)");
    r.need(2 * static_cast<std::size_t>(n), "the values");
    values.resize(n);
    for (auto& v : values) v = r.int16("the values") / 100.0;
  }
  return values;
}

std::vector<double> readMgh(const std::string& path, std::size_t vertexCount) {
  const std::string file = readFileBytes(path);
  const bool gz = file.size() >= 2 && static_cast<unsigned char>(file[0]) == 0x1F &&
                  static_cast<unsigned char>(file[1]) == 0x8B;
  constexpr std::size_t kHeader = 284;
  std::string inflated;
  auto prefix = [&](std::size_t bytes) -> const std::string& {
    if (!gz) return file;
    const std::string problem = inflatePrefix(file, bytes, inflated);
    if (!problem.empty()) throw MeshFileError(path + ": " + problem);
    return inflated;
  };
  // The header says how many bytes the values take; only those are read
  // (a .mgz's stream goes on with optional tags).
  const std::string& head = prefix(kHeader);
  if (head.size() < kHeader) throw MeshFileError(path + ": the file ends in the MGH header");
  BigEndianReader r(head, path);
  const std::int32_t version = r.int32("the header");
  if (version != 1) throw MeshFileError(path + ": not an MGH file (version " + std::to_string(version) + ", 1 expected)");
  const std::int32_t w = r.int32("the header"), h = r.int32("the header"), d = r.int32("the header"),
                     frames = r.int32("the header"), type = r.int32("the header");
  if (w < 1 || h < 1 || d < 1 || frames < 1) throw MeshFileError(path + ": MGH dimensions must be positive");
  const std::uint64_t voxels = std::uint64_t(w) * std::uint64_t(h) * std::uint64_t(d);
  if (voxels != vertexCount)
    throw MeshFileError(path + ": " + std::to_string(voxels) + " values per frame for a surface of " +
                        std::to_string(vertexCount) + " vertices");
  if (frames != 1) throw MeshFileError(path + ": " + std::to_string(frames) + " frames (one value per vertex expected)");
  std::size_t size = 0;
  switch (type) {
    case 0: size = 1; break;  // MRI_UCHAR
    case 1: size = 4; break;  // MRI_INT
    case 3: size = 4; break;  // MRI_FLOAT
    case 4: size = 2; break;  // MRI_SHORT
    default: throw MeshFileError(path + ": unsupported MGH data type " + std::to_string(type));
  }
  const std::string& all = prefix(kHeader + voxels * size);
  if (all.size() < kHeader + voxels * size) throw MeshFileError(path + ": the file ends in the values");
  std::vector<double> values(voxels);
  const char* p = all.data() + kHeader;
  for (std::size_t i = 0; i < voxels; ++i, p += size)
    values[i] = type == 0   ? double(static_cast<unsigned char>(*p))
                : type == 1 ? double(loadNumber<std::int32_t>(p, true))
                : type == 3 ? double(loadNumber<float>(p, true))
                            : double(loadNumber<std::int16_t>(p, true));
  return values;
}

VertexRegions readAnnot(const std::string& path, std::size_t vertexCount) {
  const std::string bytes = readFileBytes(path);
  BigEndianReader r(bytes, path);
  const std::int32_t n = r.int32("the vertex count");
  if (n < 0 || static_cast<std::size_t>(n) != vertexCount)
    throw MeshFileError(path + ": an annotation of " + std::to_string(n) + " vertices for a surface of " +
                        std::to_string(vertexCount));
  r.need(8 * static_cast<std::size_t>(n), "the vertices' colours");
  std::vector<std::int32_t> colour(vertexCount, 0);
  for (std::int32_t i = 0; i < n; ++i) {
    const std::int32_t v = r.int32("the vertices"), c = r.int32("the vertices");
    if (v < 0 || static_cast<std::size_t>(v) >= vertexCount)
      throw MeshFileError(path + ": entry " + std::to_string(i) + " names vertex " + std::to_string(v) +
                          " (the surface has " + std::to_string(vertexCount) + ")");
    colour[static_cast<std::size_t>(v)] = c;
  }
  VertexRegions regions;
  regions.key.assign(vertexCount, VertexRegions::kNoRegion);
  if (r.left() == 0) throw MeshFileError(path + ": the annotation has no colour table");
  const std::int32_t tag = r.int32("the colour table tag");
  if (tag != 1) throw MeshFileError(path + ": unknown tag " + std::to_string(tag) + " where the colour table (1) belongs");
  auto string = [&](const std::string& what) {
    const std::int32_t length = r.int32(what);
    if (length < 0 || static_cast<std::size_t>(length) > r.left())
      throw MeshFileError(path + ": the file ends in " + what);
    std::string t = r.text(static_cast<std::size_t>(length), what);
    while (!t.empty() && t.back() == '\0') t.pop_back();
    return t;
  };
  // FreeSurfer's packing r + 256 g + 65536 b, in unsigned arithmetic: a
  // hostile table's colours outside 0..255 wrap (as in FreeSurfer's int
  // arithmetic on two's complement) instead of overflowing a signed int.
  const auto packedColour = [](std::int32_t red, std::int32_t green, std::int32_t blue) {
    const std::uint32_t packed = static_cast<std::uint32_t>(red) + static_cast<std::uint32_t>(green) * 256u +
                                 static_cast<std::uint32_t>(blue) * 65536u;
    return static_cast<std::int32_t>(packed);
  };
  std::map<std::int32_t, std::int32_t> keyOfColour;  // packed colour -> structure index
  std::int32_t entries = r.int32("the colour table");
  if (entries > 0) {
    // The old colour table: entries, the table's file name, then per entry
    // its name and r, g, b, transparency; the structure index is the order.
    string("the colour table's file name");
    for (std::int32_t e = 0; e < entries; ++e) {
      const std::string name = string("a colour table entry");
      const std::int32_t red = r.int32("a colour"), green = r.int32("a colour"), blue = r.int32("a colour");
      r.int32("a colour");
      keyOfColour[packedColour(red, green, blue)] = e;
      regions.name[e] = name;
    }
  } else {
    // A negative count is minus the table's version (in 64 bits: the
    // negation of INT32_MIN does not fit an int32).
    const std::int64_t version = -static_cast<std::int64_t>(entries);
    if (version != 2) throw MeshFileError(path + ": colour table version " + std::to_string(version) + " (2 expected)");
    r.int32("the colour table's size");
    string("the colour table's file name");
    const std::int32_t count = r.int32("the colour table's entry count");
    if (count < 0 || static_cast<std::size_t>(count) > r.left() / 20)
      throw MeshFileError(path + ": the file ends in the colour table");
    for (std::int32_t e = 0; e < count; ++e) {
      const std::int32_t index = r.int32("a colour table entry");
      const std::string name = string("a colour table entry");
      const std::int32_t red = r.int32("a colour"), green = r.int32("a colour"), blue = r.int32("a colour");
      r.int32("a colour");
      if (regions.name.count(index))
        throw MeshFileError(path + ": structure " + std::to_string(index) + " appears twice in the colour table");
      keyOfColour[packedColour(red, green, blue)] = index;
      regions.name[index] = name;
    }
  }
  for (std::size_t v = 0; v < vertexCount; ++v) {
    const auto found = keyOfColour.find(colour[v]);
    if (found != keyOfColour.end()) regions.key[v] = found->second;
  }
  return regions;
}

VertexRegions readLabelFile(const std::string& path, std::size_t vertexCount) {
  const std::string text = readFileBytes(path);
  std::istringstream in(text);
  std::string line;
  std::size_t lineNumber = 0;
  auto next = [&]() {
    while (std::getline(in, line)) {
      ++lineNumber;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (line.find_first_not_of(" \t") != std::string::npos) return true;
    }
    return false;
  };
  const std::string at = path + ": line ";
  if (!next()) throw MeshFileError(path + ": the label file is empty");
  if (line[0] == '#' && !next()) throw MeshFileError(path + ": the label file has no vertex count");
  char* end = nullptr;
  const long long count = std::strtoll(line.c_str(), &end, 10);
  if (end == line.c_str() || count < 0 || line.find_first_not_of(" \t", end - line.c_str()) != std::string::npos)
    throw MeshFileError(at + std::to_string(lineNumber) + ": expected the vertex count");
  VertexRegions regions;
  regions.key.assign(vertexCount, VertexRegions::kNoRegion);
  std::string name = baseName(path);
  if (name.size() > 6 && name.compare(name.size() - 6, 6, ".label") == 0) name.resize(name.size() - 6);
  regions.name[1] = name;
  for (long long i = 0; i < count; ++i) {
    if (!next())
      throw MeshFileError(path + ": the file ends after " + std::to_string(i) + " of " + std::to_string(count) +
                          " vertices");
    std::istringstream row(line);
    long long v;
    double x, y, z, value;
    if (!(row >> v >> x >> y >> z >> value))
      throw MeshFileError(at + std::to_string(lineNumber) + ": expected \"vertex x y z value\"");
    if (v < 0 || static_cast<std::size_t>(v) >= vertexCount)
      throw MeshFileError(at + std::to_string(lineNumber) + ": vertex " + std::to_string(v) +
                          " does not exist (the surface has " + std::to_string(vertexCount) + ")");
    regions.key[static_cast<std::size_t>(v)] = 1;
  }
  return regions;
}

SurfaceMesh readFreeSurferSurfaceBytes(const std::string& path, const std::string& bytes) {
  BigEndianReader r(bytes, path);
  const std::uint32_t magic = r.int24("the magic number");
  if (magic == kQuadMagic || magic == kNewQuadMagic)
    throw MeshFileError(path + ": a FreeSurfer quadrangle surface (only the triangle format is read)");
  if (magic != kTriangleMagic) throw MeshFileError(path + ": not a FreeSurfer surface (no triangle magic number)");
  // "created by ... on ...\n\n" (nibabel and FreeSurfer write two newlines).
  const std::size_t stampEnd = bytes.find('\n', 3);
  if (stampEnd == std::string::npos || stampEnd + 1 >= bytes.size())
    throw MeshFileError(path + ": the file ends in the creation line");
  r.skip(stampEnd + 1 - 3);
  if (bytes[stampEnd + 1] == '\n') r.skip(1);
  const std::int32_t nv = r.int32("the vertex count"), nf = r.int32("the face count");
  if (nv <= 0 || nf <= 0) throw MeshFileError(path + ": the surface has no vertices or no faces");
  r.need(12 * std::size_t(nv), "the vertices");
  r.need(12 * std::size_t(nv) + 12 * std::size_t(nf), "the triangles");
  SurfaceMesh m;
  m.format = "freesurfer";
  m.coordinateType = ScalarType::Float32;
  m.points.resize(static_cast<std::size_t>(nv));
  for (std::int32_t v = 0; v < nv; ++v) {
    const double x = r.float32("the vertices"), y = r.float32("the vertices"), z = r.float32("the vertices");
    if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
      throw MeshFileError(path + ": vertex " + std::to_string(v) + " has a coordinate that is not finite");
    m.points[static_cast<std::size_t>(v)] = {x, y, z};
  }
  m.faces.faceVertex.reserve(3 * std::size_t(nf));
  m.faces.faceStart.reserve(std::size_t(nf) + 1);
  for (std::int32_t f = 0; f < nf; ++f) {
    VertexId c[3];
    for (int k = 0; k < 3; ++k) {
      const std::int32_t v = r.int32("the triangles");
      if (v < 0 || v >= nv)
        throw MeshFileError(path + ": triangle " + std::to_string(f) + " refers to vertex " + std::to_string(v) +
                            " (the surface has " + std::to_string(nv) + ")");
      c[k] = static_cast<VertexId>(v);
    }
    m.faces.add({c[0], c[1], c[2]});
  }
  // Tags after the triangles (FreeSurfer's old-style tags, no length):
  // useRealRAS (2) and the volume geometry (20). Others end the reading.
  bool realRas = false, geometry = false;
  while (r.left() >= 4) {
    const std::int32_t tag = r.int32("a tag");
    if (tag == kTagOldUseRealRas) {
      realRas = r.int32("the useRealRAS tag") != 0;
    } else if (tag == kTagOldSurfaceGeometry) {
      // Eight lines of text.
      std::size_t end = r.at();
      for (int line = 0; line < 8 && end != std::string::npos; ++line) {
        end = bytes.find('\n', end);
        if (end != std::string::npos) ++end;
      }
      const std::string block = bytes.substr(r.at(), (end == std::string::npos ? bytes.size() : end) - r.at());
      geometry = volumeGeometryTransform(block, m.coordinates.transform);
      break;
    } else {
      break;
    }
  }
  m.coordinates.space = realRas ? "scanner RAS" : "tkr-RAS";
  if (geometry && !realRas) {
    m.coordinates.hasTransform = true;
    m.coordinates.transformedSpace = "scanner RAS";
  } else {
    m.coordinates.transform = {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1};
  }
  const std::string name = baseName(path);
  if (name.rfind("lh.", 0) == 0) m.anatomicalStructure = "CortexLeft";
  if (name.rfind("rh.", 0) == 0) m.anatomicalStructure = "CortexRight";
  return m;
}

}  // namespace stvd::surface_io::detail
