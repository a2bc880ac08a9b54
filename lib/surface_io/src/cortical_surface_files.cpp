// The entry points of cortical_surface_files.hpp: which format a path is,
// GIfTI values and labels, and the per-vertex writers.
#include "stvd/surface_io/cortical_surface_files.hpp"

#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "encoded_data.hpp"
#include "freesurfer_files.hpp"
#include "gifti_files.hpp"
#include "stvd/system/files/regular_file.hpp"

namespace stvd::surface_io {
namespace {

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}
bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && lower(s.substr(s.size() - tail.size())) == tail;
}
std::string baseName(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

/// The one per-vertex array of a GIfTI values or label file.
const detail::GiftiArray& vertexArray(const detail::GiftiDocument& doc, const std::string& path,
                                      std::size_t vertexCount) {
  if (doc.arrays.empty()) throw MeshFileError(path + ": the GIfTI file has no data array");
  const detail::GiftiArray& a = doc.arrays.front();
  if (a.intent == "NIFTI_INTENT_POINTSET" || a.intent == "NIFTI_INTENT_TRIANGLE")
    throw MeshFileError(path + ": a GIfTI surface, not per-vertex data");
  if (a.dims.empty() || (a.dims.size() == 2 && a.dims[1] != 1) || a.dims.size() > 2)
    throw MeshFileError(path + ": the first data array must hold one value per vertex (N or N x 1)");
  if (a.dims[0] != vertexCount)
    throw MeshFileError(path + ": " + std::to_string(a.dims[0]) + " values for a surface of " +
                        std::to_string(vertexCount) + " vertices");
  return a;
}

}  // namespace

bool isGiftiPath(const std::string& path) { return endsWith(path, ".gii"); }

bool hasFreeSurferHemisphereName(const std::string& path) {
  const std::string name = baseName(path);
  return name.size() > 3 && (name.rfind("lh.", 0) == 0 || name.rfind("rh.", 0) == 0);
}

bool isFreeSurferSurfaceFile(const std::string& path) {
  if (!files::isReadableRegularFile(path)) return false;
  try {
    const std::string head = files::readRegularFile(path, 3, true);
    return head.size() == 3 && static_cast<unsigned char>(head[0]) == 0xFF &&
           static_cast<unsigned char>(head[1]) == 0xFF && static_cast<unsigned char>(head[2]) == 0xFE;
  } catch (const files::InputFileError&) {
    return false;
  }
}

SurfaceMesh readFreeSurferSurface(const std::string& path) {
  return detail::readFreeSurferSurfaceBytes(path, detail::readFileBytes(path));
}

bool isVertexValuesPath(const std::string& path) {
  return isGiftiPath(path) || endsWith(path, ".mgh") || endsWith(path, ".mgz") || endsWith(path, ".curv") ||
         hasFreeSurferHemisphereName(path);
}

std::vector<double> readVertexValues(const std::string& path, std::size_t vertexCount) {
  if (isGiftiPath(path)) return vertexArray(detail::readGifti(path), path, vertexCount).values;
  if (endsWith(path, ".mgh") || endsWith(path, ".mgz")) return detail::readMgh(path, vertexCount);
  return detail::readCurv(path, detail::readFileBytes(path), vertexCount);
}

bool isVertexRegionsPath(const std::string& path) {
  return endsWith(path, ".annot") || endsWith(path, ".label") || endsWith(path, ".label.gii");
}

VertexRegions readVertexRegions(const std::string& path, std::size_t vertexCount) {
  if (endsWith(path, ".annot")) return detail::readAnnot(path, vertexCount);
  if (endsWith(path, ".label")) return detail::readLabelFile(path, vertexCount);
  if (!isGiftiPath(path))
    throw MeshFileError(path + ": unknown region file (expected .annot, .label or .label.gii)");
  const detail::GiftiDocument doc = detail::readGifti(path);
  const detail::GiftiArray& a = vertexArray(doc, path, vertexCount);
  if (a.intent != "NIFTI_INTENT_LABEL")
    throw MeshFileError(path + ": the data array's intent is " + a.intent + ", not NIFTI_INTENT_LABEL");
  VertexRegions regions;
  const detail::XmlElement* table = doc.root.child("LabelTable");
  if (table)
    for (const detail::XmlElement& label : table->children) {
      if (label.name != "Label") continue;
      const std::string* key = label.attribute("Key");
      char* end = nullptr;
      const long k = key ? std::strtol(key->c_str(), &end, 10) : 0;
      if (!key || end == key->c_str() || *end != '\0' || k < INT32_MIN || k > INT32_MAX)
        throw MeshFileError(path + ": line " + std::to_string(label.line) + ": a Label needs an integer Key");
      std::string name = label.text;
      const std::size_t b = name.find_first_not_of(" \t\r\n"), e = name.find_last_not_of(" \t\r\n");
      regions.name[static_cast<std::int32_t>(k)] = b == std::string::npos ? std::string() : name.substr(b, e - b + 1);
    }
  regions.key.resize(vertexCount);
  for (std::size_t v = 0; v < vertexCount; ++v) {
    const double x = a.values[v];
    if (x != std::floor(x) || x < INT32_MIN || x > INT32_MAX)
      throw MeshFileError(path + ": vertex " + std::to_string(v) + " has label " + std::to_string(x) +
                          ", not an integer key");
    regions.key[v] = static_cast<std::int32_t>(x);
  }
  return regions;
}

std::vector<VertexId> regionVertices(const VertexRegions& regions, const std::string& name, const std::string& path) {
  const std::int32_t* key = nullptr;
  for (const auto& [k, n] : regions.name)
    if (n == name) key = &k;
  if (!key) {
    std::string names;
    std::size_t listed = 0;
    for (const auto& entry : regions.name) {
      if (listed++ == 40) {
        names += ", ...";
        break;
      }
      names += (names.empty() ? "" : ", ") + entry.second;
    }
    throw MeshFileError(path + ": no region named \"" + name + "\" (the file names " +
                        (names.empty() ? std::string("none") : names) + ")");
  }
  std::vector<VertexId> vertices;
  for (std::size_t v = 0; v < regions.key.size(); ++v)
    if (regions.key[v] == *key) vertices.push_back(static_cast<VertexId>(v));
  if (vertices.empty()) throw MeshFileError(path + ": region \"" + name + "\" has no vertex");
  return vertices;
}

VertexValuesFormat vertexValuesFormatOf(const std::string& path) {
  if (isGiftiPath(path))
    return endsWith(path, ".surf.gii") || endsWith(path, ".label.gii") ? VertexValuesFormat::None
                                                                        : VertexValuesFormat::Gifti;
  if (endsWith(path, ".curv")) return VertexValuesFormat::FreeSurferCurv;
  if (hasFreeSurferHemisphereName(path)) {
    // lh.distance is a curv file; lh.distance.ply is not.
    for (const char* other : {".ply", ".vtk", ".csv", ".obj", ".off", ".stl", ".mgh", ".mgz", ".annot", ".label"})
      if (endsWith(path, other)) return VertexValuesFormat::None;
    return VertexValuesFormat::FreeSurferCurv;
  }
  return VertexValuesFormat::None;
}

namespace {

std::string xmlEscaped(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '<') out += "&lt;";
    else if (c == '>') out += "&gt;";
    else if (c == '&') out += "&amp;";
    else if (c == '"') out += "&quot;";
    else out += c;
  }
  return out;
}

}  // namespace

void writeVertexValues(const std::string& path, const std::string& formatPath, const SurfaceMesh& mesh,
                       const std::vector<double>& values, const std::string& name) {
  if (values.size() != mesh.points.size())
    throw MeshFileError(path + ": " + std::to_string(values.size()) + " values for " +
                        std::to_string(mesh.points.size()) + " vertices");
  const VertexValuesFormat format = vertexValuesFormatOf(formatPath);
  std::string bytes;
  if (format == VertexValuesFormat::Gifti) {
    std::string data;
    data.reserve(4 * values.size());
    for (const double v : values) detail::storeNumber(data, static_cast<float>(v), false);
    const bool shape = endsWith(formatPath, ".shape.gii");
    // Compressed, as NiBabel and Connectome Workbench write GIfTI data (the
    // distances of a 163,842-vertex surface: 0.75 MB instead of 0.87).
    std::string packed;
    if (!detail::deflateZlib(data, packed)) throw MeshFileError(path + ": zlib could not compress the values");
    std::ostringstream x;
    x << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
      << "<GIFTI Version=\"1.0\" NumberOfDataArrays=\"1\">\n"
      << "  <MetaData>\n";
    if (!mesh.anatomicalStructure.empty())
      x << "    <MD><Name><![CDATA[AnatomicalStructurePrimary]]></Name><Value><![CDATA["
        << mesh.anatomicalStructure << "]]></Value></MD>\n";
    x << "    <MD><Name><![CDATA[generator]]></Name><Value><![CDATA[stvd]]></Value></MD>\n"
      << "  </MetaData>\n  <LabelTable/>\n"
      << "  <DataArray Intent=\"" << (shape ? "NIFTI_INTENT_SHAPE" : "NIFTI_INTENT_NONE")
      << "\" DataType=\"NIFTI_TYPE_FLOAT32\" ArrayIndexingOrder=\"RowMajorOrder\" Dimensionality=\"1\" Dim0=\""
      << values.size() << "\" Encoding=\"GZipBase64Binary\" Endian=\"LittleEndian\" ExternalFileName=\"\" "
      << "ExternalFileOffset=\"\">\n"
      << "    <MetaData>\n      <MD><Name><![CDATA[Name]]></Name><Value><![CDATA[" << xmlEscaped(name)
      << "]]></Value></MD>\n    </MetaData>\n"
      << "    <Data>" << detail::encodeBase64(packed) << "</Data>\n  </DataArray>\n</GIFTI>\n";
    bytes = x.str();
  } else if (format == VertexValuesFormat::FreeSurferCurv) {
    bytes.reserve(15 + 4 * values.size());
    bytes += "\xFF\xFF\xFF";
    detail::storeNumber(bytes, static_cast<std::int32_t>(values.size()), true);
    detail::storeNumber(bytes, static_cast<std::int32_t>(mesh.faces.faceCount()), true);
    detail::storeNumber(bytes, std::int32_t{1}, true);
    for (const double v : values) detail::storeNumber(bytes, static_cast<float>(v), true);
  } else {
    throw MeshFileError(formatPath + ": not a per-vertex output (.shape.gii, .func.gii, .gii, .curv or lh.* / rh.*)");
  }
  std::ofstream out(path, std::ios::binary);
  if (!out) throw MeshFileError(path + ": cannot create the file: " + std::strerror(errno));
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  out.close();
  if (!out) throw MeshFileError(path + ": cannot write the file (disk full or file size limit?)");
}

}  // namespace stvd::surface_io
