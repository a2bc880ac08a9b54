// GIfTI (GIFTI Surface Data Format 1.0): surfaces, per-vertex values and
// label tables; the per-vertex writer. The XML is read by xml_elements.cpp,
// the encodings decoded here.
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

#include "encoded_data.hpp"
#include "gifti_files.hpp"
#include "stvd/surface_io/cortical_surface_files.hpp"
#include "stvd/system/files/regular_file.hpp"
#include "xml_elements.hpp"

namespace stvd::surface_io::detail {
namespace {

std::string readAll(const std::string& path) {
  try {
    return files::readRegularFile(path);
  } catch (const files::InputFileError& e) {
    throw MeshFileError(path + ": " + (e.problem() == "no such file" ? "cannot open the file: No such file or directory"
                                                                      : e.problem()));
  }
}

struct DataType {
  const char* name;
  std::size_t bytes;
  char kind;  // 'u' unsigned, 'i' signed, 'f' float
};
constexpr DataType kDataTypes[] = {
    {"NIFTI_TYPE_UINT8", 1, 'u'},  {"NIFTI_TYPE_INT8", 1, 'i'},    {"NIFTI_TYPE_UINT16", 2, 'u'},
    {"NIFTI_TYPE_INT16", 2, 'i'},  {"NIFTI_TYPE_UINT32", 4, 'u'},  {"NIFTI_TYPE_INT32", 4, 'i'},
    {"NIFTI_TYPE_UINT64", 8, 'u'}, {"NIFTI_TYPE_INT64", 8, 'i'},   {"NIFTI_TYPE_FLOAT32", 4, 'f'},
    {"NIFTI_TYPE_FLOAT64", 8, 'f'}};

double loadValue(const char* p, const DataType& t, bool big) {
  switch (t.bytes) {
    case 1: return t.kind == 'u' ? double(loadNumber<std::uint8_t>(p, big)) : double(loadNumber<std::int8_t>(p, big));
    case 2: return t.kind == 'u' ? double(loadNumber<std::uint16_t>(p, big)) : double(loadNumber<std::int16_t>(p, big));
    case 4:
      return t.kind == 'f'   ? double(loadNumber<float>(p, big))
             : t.kind == 'u' ? double(loadNumber<std::uint32_t>(p, big))
                             : double(loadNumber<std::int32_t>(p, big));
    default:
      return t.kind == 'f'   ? loadNumber<double>(p, big)
             : t.kind == 'u' ? double(loadNumber<std::uint64_t>(p, big))
                             : double(loadNumber<std::int64_t>(p, big));
  }
}

std::string attributeOr(const XmlElement& e, const std::string& key, const std::string& otherwise) {
  const std::string* v = e.attribute(key);
  return v ? *v : otherwise;
}

}  // namespace

std::string metaDataValue(const XmlElement& owner, const std::string& name) {
  const XmlElement* meta = owner.child("MetaData");
  if (!meta) return "";
  for (const XmlElement& md : meta->children) {
    if (md.name != "MD") continue;
    const XmlElement* n = md.child("Name");
    const XmlElement* v = md.child("Value");
    if (n && v && n->text == name) return v->text;
  }
  return "";
}

GiftiArray decodeArray(const XmlElement& da, const std::string& path, std::size_t index) {
  const std::string where = path + ": DataArray " + std::to_string(index) + ": ";
  GiftiArray a;
  a.element = &da;
  a.intent = attributeOr(da, "Intent", "NIFTI_INTENT_NONE");
  const std::string typeName = attributeOr(da, "DataType", "");
  const DataType* type = nullptr;
  for (const DataType& t : kDataTypes)
    if (typeName == t.name) type = &t;
  if (!type) throw MeshFileError(where + "unsupported DataType \"" + typeName + "\"");
  long long dimensionality = 0;
  {
    const std::string text = attributeOr(da, "Dimensionality", "");
    char* end = nullptr;
    dimensionality = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || dimensionality < 1 || dimensionality > 6)
      throw MeshFileError(where + "Dimensionality must be 1 to 6, not \"" + text + "\"");
  }
  std::size_t count = 1;
  for (long long d = 0; d < dimensionality; ++d) {
    const std::string key = "Dim" + std::to_string(d);
    const std::string text = attributeOr(da, key, "");
    char* end = nullptr;
    errno = 0;
    const long long n = std::strtoll(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || errno != 0 || n < 0 || n > (1LL << 31))
      throw MeshFileError(where + key + " must be a count from 0 to 2^31, not \"" + text + "\"");
    a.dims.push_back(static_cast<std::size_t>(n));
    if (n != 0 && count > (std::size_t{1} << 31) / static_cast<std::size_t>(n))
      throw MeshFileError(where + "more than 2^31 values");
    count *= static_cast<std::size_t>(n);
  }
  const std::string encoding = attributeOr(da, "Encoding", "");
  const std::string endian = attributeOr(da, "Endian", "LittleEndian");
  const std::string order = attributeOr(da, "ArrayIndexingOrder", "RowMajorOrder");
  if (endian != "LittleEndian" && endian != "BigEndian")
    throw MeshFileError(where + "Endian must be LittleEndian or BigEndian, not \"" + endian + "\"");
  if (order != "RowMajorOrder" && order != "ColumnMajorOrder")
    throw MeshFileError(where + "ArrayIndexingOrder must be RowMajorOrder or ColumnMajorOrder, not \"" + order + "\"");
  const XmlElement* data = da.child("Data");
  const std::string empty;
  const std::string& text = data ? data->text : empty;
  std::vector<double> values;
  if (encoding == "ASCII") {
    values.reserve(std::min(count, text.size() / 2 + 1));
    const char* p = text.c_str();
    const char* end = p + text.size();
    while (p < end) {
      while (p < end && std::isspace(static_cast<unsigned char>(*p))) ++p;
      if (p >= end) break;
      char* next = nullptr;
      const double x = std::strtod(p, &next);
      if (next == p) throw MeshFileError(where + "ASCII data: \"" + std::string(p, std::min<std::size_t>(20, end - p)) + "\" is not a number");
      if (values.size() == count) throw MeshFileError(where + "ASCII data hold more than the " + std::to_string(count) + " values of its dimensions");
      // The array's type holds the value: FLOAT32 text is a float32.
      values.push_back(type->kind == 'f' && type->bytes == 4 ? static_cast<double>(static_cast<float>(x)) : x);
      p = next;
    }
    if (values.size() != count)
      throw MeshFileError(where + "ASCII data hold " + std::to_string(values.size()) + " values, its dimensions " +
                          std::to_string(count));
  } else if (encoding == "Base64Binary" || encoding == "GZipBase64Binary") {
    std::string bytes;
    if (!decodeBase64(text, bytes)) throw MeshFileError(where + "the data are not valid base64");
    if (encoding == "GZipBase64Binary") {
      std::string inflated;
      const std::string problem = inflateExactly(bytes, count * type->bytes, inflated);
      if (!problem.empty()) throw MeshFileError(where + "GZipBase64Binary data: " + problem);
      bytes.swap(inflated);
    }
    if (bytes.size() != count * type->bytes)
      throw MeshFileError(where + "the data hold " + std::to_string(bytes.size()) + " bytes, its dimensions and type " +
                          std::to_string(count * type->bytes));
    values.resize(count);
    const bool big = endian == "BigEndian";
    for (std::size_t i = 0; i < count; ++i) values[i] = loadValue(bytes.data() + i * type->bytes, *type, big);
  } else if (encoding == "ExternalFileBinary") {
    throw MeshFileError(where + "the data are in an external file (ExternalFileBinary), which stvd does not follow");
  } else {
    throw MeshFileError(where + "unknown Encoding \"" + encoding + "\" (ASCII, Base64Binary or GZipBase64Binary)");
  }
  // Row-major from here on: a column-major N x M array is transposed.
  if (order == "ColumnMajorOrder" && a.dims.size() == 2 && a.dims[1] > 1) {
    const std::size_t rows = a.dims[0], cols = a.dims[1];
    std::vector<double> t(values.size());
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t c = 0; c < cols; ++c) t[r * cols + c] = values[c * rows + r];
    values.swap(t);
  } else if (order == "ColumnMajorOrder" && a.dims.size() > 2) {
    throw MeshFileError(where + "column-major arrays of more than 2 dimensions are not supported");
  }
  a.values = std::move(values);
  return a;
}

GiftiDocument readGifti(const std::string& path) {
  GiftiDocument doc;
  doc.root = parseXml(readAll(path), path);
  if (doc.root.name != "GIFTI") throw MeshFileError(path + ": not a GIfTI file (the root element is <" + doc.root.name + ">)");
  std::size_t index = 0;
  for (const XmlElement& c : doc.root.children)
    if (c.name == "DataArray") doc.arrays.push_back(decodeArray(c, path, index++));
  return doc;
}

}  // namespace stvd::surface_io::detail

namespace stvd::surface_io {

using detail::GiftiArray;
using detail::GiftiDocument;

SurfaceMesh readGiftiSurface(const std::string& path) {
  const GiftiDocument doc = detail::readGifti(path);
  const GiftiArray* points = nullptr;
  const GiftiArray* triangles = nullptr;
  for (const GiftiArray& a : doc.arrays) {
    if (a.intent == "NIFTI_INTENT_POINTSET") {
      if (points) throw MeshFileError(path + ": more than one NIFTI_INTENT_POINTSET array");
      points = &a;
    } else if (a.intent == "NIFTI_INTENT_TRIANGLE") {
      if (triangles) throw MeshFileError(path + ": more than one NIFTI_INTENT_TRIANGLE array");
      triangles = &a;
    }
  }
  if (!points || !triangles)
    throw MeshFileError(path + ": not a GIfTI surface (it needs a NIFTI_INTENT_POINTSET and a NIFTI_INTENT_TRIANGLE "
                               "array; per-vertex files go to --metric, --seeds or --mask)");
  if (points->dims.size() != 2 || points->dims[1] != 3)
    throw MeshFileError(path + ": the NIFTI_INTENT_POINTSET array must be N x 3");
  if (triangles->dims.size() != 2 || triangles->dims[1] != 3)
    throw MeshFileError(path + ": the NIFTI_INTENT_TRIANGLE array must be F x 3");
  SurfaceMesh m;
  m.format = "gifti";
  m.coordinateType = ScalarType::Float64;
  const std::string* type = points->element->attribute("DataType");
  if (type && *type == "NIFTI_TYPE_FLOAT32") m.coordinateType = ScalarType::Float32;
  const std::size_t n = points->dims[0];
  m.points.resize(n);
  for (std::size_t v = 0; v < n; ++v) {
    const double* p = &points->values[3 * v];
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw MeshFileError(path + ": vertex " + std::to_string(v) + " has a coordinate that is not finite");
    m.points[v] = {p[0], p[1], p[2]};
  }
  const std::size_t f = triangles->dims[0];
  m.faces.faceVertex.reserve(3 * f);
  m.faces.faceStart.reserve(f + 1);
  for (std::size_t t = 0; t < f; ++t) {
    VertexId corner[3];
    for (int c = 0; c < 3; ++c) {
      const double x = triangles->values[3 * t + c];
      if (!(x >= 0) || x >= static_cast<double>(n) || x != std::floor(x))
        throw MeshFileError(path + ": triangle " + std::to_string(t) + " refers to vertex " + std::to_string(x) +
                            " (the surface has " + std::to_string(n) + ")");
      corner[c] = static_cast<VertexId>(x);
    }
    m.faces.add({corner[0], corner[1], corner[2]});
  }
  if (n == 0) throw MeshFileError(path + ": the file has no vertices");
  if (f == 0) throw MeshFileError(path + ": the file has no faces");
  // The pointset's coordinate system: the first transform (GIfTI allows
  // several; Connectome Workbench and nibabel write one).
  if (const detail::XmlElement* cs = points->element->child("CoordinateSystemTransformMatrix")) {
    const detail::XmlElement* data = cs->child("DataSpace");
    const detail::XmlElement* transformed = cs->child("TransformedSpace");
    const detail::XmlElement* matrix = cs->child("MatrixData");
    auto trimmed = [](std::string s) {
      const std::size_t b = s.find_first_not_of(" \t\r\n"), e = s.find_last_not_of(" \t\r\n");
      return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
    };
    if (data) m.coordinates.space = trimmed(data->text);
    if (transformed) m.coordinates.transformedSpace = trimmed(transformed->text);
    if (matrix) {
      std::istringstream in(matrix->text);
      std::array<double, 16> t{};
      std::size_t k = 0;
      double x;
      while (k < 16 && in >> x) t[k++] = x;
      std::string rest;
      if (k != 16 || (in >> rest))
        throw MeshFileError(path + ": the CoordinateSystemTransformMatrix's MatrixData must hold 16 numbers");
      m.coordinates.transform = t;
      m.coordinates.hasTransform = true;
    }
  }
  m.anatomicalStructure = detail::metaDataValue(*points->element, "AnatomicalStructurePrimary");
  if (m.anatomicalStructure.empty()) m.anatomicalStructure = detail::metaDataValue(doc.root, "AnatomicalStructurePrimary");
  return m;
}

}  // namespace stvd::surface_io
