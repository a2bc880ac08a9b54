// GIfTI and FreeSurfer files written byte by byte here (the NiBabel
// round trips are in tests/python/test_cortical_surfaces.py): every
// encoding, byte order and array order of GIfTI, FreeSurfer's surfaces with
// their volume geometry, curv (both formats), .mgh/.mgz, annotations (both
// colour tables), labels; and hostile files, each one clear error naming
// the file, never a crash, a hang or a huge allocation.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "stvd/surface_io/cortical_surface_files.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"

namespace stvd::surface_io {
namespace {

namespace fs = std::filesystem;

template <class T>
void put(std::string& out, T value, bool big) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  const std::uint16_t one = 1;
  const bool little = *reinterpret_cast<const unsigned char*>(&one) == 1;
  if (big == little)
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(b[i], b[sizeof(T) - 1 - i]);
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

std::string base64(const std::string& bytes) {
  const char* a = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8 | (unsigned char)bytes[i + 2];
    out += {a[v >> 18 & 63], a[v >> 12 & 63], a[v >> 6 & 63], a[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16;
    out += {a[v >> 18 & 63], a[v >> 12 & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const unsigned v = (unsigned char)bytes[i] << 16 | (unsigned char)bytes[i + 1] << 8;
    out += {a[v >> 18 & 63], a[v >> 12 & 63], a[v >> 6 & 63], '='};
  }
  return out;
}

std::string zlibCompressed(const std::string& bytes) {
  uLongf size = compressBound(bytes.size());
  std::string out(size, '\0');
  compress(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(bytes.data()), bytes.size());
  out.resize(size);
  return out;
}

std::string gzipCompressed(const std::string& bytes) {
  z_stream z{};
  deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY);
  std::string out(deflateBound(&z, bytes.size()) + 32, '\0');
  z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  z.avail_in = static_cast<uInt>(bytes.size());
  z.next_out = reinterpret_cast<Bytef*>(out.data());
  z.avail_out = static_cast<uInt>(out.size());
  deflate(&z, Z_FINISH);
  out.resize(z.total_out);
  deflateEnd(&z);
  return out;
}

// A square pyramid without its base: 5 vertices, 4 triangles.
const std::vector<double> kPoints{0, 0, 1, 1, 0, 0, 0, 1, 0, -1, 0, 0, 0, -1, 0};
const std::vector<int> kTriangles{0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1};

struct ArrayFormat {
  std::string encoding = "Base64Binary";
  bool big = false;
  bool columnMajor = false;
  bool float64 = false;
};

std::string dataArray(const std::string& intent, const std::vector<double>& values, std::size_t rows,
                      std::size_t cols, bool integers, const ArrayFormat& f, const std::string& inner = "") {
  std::vector<double> ordered = values;
  if (f.columnMajor)
    for (std::size_t r = 0; r < rows; ++r)
      for (std::size_t c = 0; c < cols; ++c) ordered[c * rows + r] = values[r * cols + c];
  std::string data;
  if (f.encoding == "ASCII") {
    for (const double x : ordered) data += std::to_string(x) + (integers ? "\n" : " ");
  } else {
    std::string bytes;
    for (const double x : ordered) {
      if (integers) put(bytes, static_cast<std::int32_t>(x), f.big);
      else if (f.float64) put(bytes, x, f.big);
      else put(bytes, static_cast<float>(x), f.big);
    }
    data = base64(f.encoding == "GZipBase64Binary" ? zlibCompressed(bytes) : bytes);
  }
  const std::string type = integers ? "NIFTI_TYPE_INT32" : f.float64 ? "NIFTI_TYPE_FLOAT64" : "NIFTI_TYPE_FLOAT32";
  return "<DataArray Intent=\"" + intent + "\" DataType=\"" + type + "\" ArrayIndexingOrder=\"" +
         (f.columnMajor ? "ColumnMajorOrder" : "RowMajorOrder") + "\" Dimensionality=\"" + (cols > 1 ? "2" : "1") +
         "\" Dim0=\"" + std::to_string(rows) + "\"" + (cols > 1 ? " Dim1=\"" + std::to_string(cols) + "\"" : "") +
         " Encoding=\"" + f.encoding + "\" Endian=\"" + (f.big ? "BigEndian" : "LittleEndian") +
         "\" ExternalFileName=\"\" ExternalFileOffset=\"\">" + inner + "<Data>" + data + "</Data></DataArray>\n";
}

std::string giftiSurface(const ArrayFormat& f, const std::string& transform = "") {
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!DOCTYPE GIFTI SYSTEM \"gifti.dtd\">\n"
         "<GIFTI Version=\"1.0\" NumberOfDataArrays=\"2\">\n<!-- a comment -->\n" +
         dataArray("NIFTI_INTENT_POINTSET", kPoints, 5, 3, false, f,
                   "<MetaData><MD><Name><![CDATA[AnatomicalStructurePrimary]]></Name><Value>CortexLeft</Value>"
                   "</MD></MetaData>" +
                       transform) +
         dataArray("NIFTI_INTENT_TRIANGLE", std::vector<double>(kTriangles.begin(), kTriangles.end()), 4, 3, true, f) +
         "</GIFTI>\n";
}

std::string freeSurferSurface(const std::string& footer = "") {
  std::string b = "\xFF\xFF\xFE" + std::string("created by stvd's tests on today\n\n");
  put(b, std::int32_t{5}, true);
  put(b, std::int32_t{4}, true);
  for (const double x : kPoints) put(b, static_cast<float>(x), true);
  for (const int v : kTriangles) put(b, std::int32_t{v}, true);
  return b + footer;
}

class CorticalFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              ("stvd-cortical-" + std::to_string(::getpid()) + "-" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  std::string write(const std::string& name, const std::string& bytes) const {
    const std::string p = (folder_ / name).string();
    std::ofstream(p, std::ios::binary) << bytes;
    return p;
  }
  template <class F>
  static std::string errorOf(F&& read) {
    try {
      read();
    } catch (const MeshFileError& e) {
      return e.what();
    }
    return "";
  }
  static void expectPyramid(const SurfaceMesh& m) {
    ASSERT_EQ(m.points.size(), 5u);
    ASSERT_EQ(m.faces.faceCount(), 4u);
    for (std::size_t v = 0; v < 5; ++v) {
      EXPECT_EQ(m.points[v].x, kPoints[3 * v]);
      EXPECT_EQ(m.points[v].y, kPoints[3 * v + 1]);
      EXPECT_EQ(m.points[v].z, kPoints[3 * v + 2]);
    }
    for (std::size_t c = 0; c < 12; ++c) EXPECT_EQ(m.faces.faceVertex[c], static_cast<VertexId>(kTriangles[c]));
  }
  fs::path folder_;
};

TEST_F(CorticalFiles, GiftiSurfacesInEveryEncodingByteOrderAndArrayOrder) {
  for (const char* encoding : {"ASCII", "Base64Binary", "GZipBase64Binary"})
    for (const bool big : {false, true})
      for (const bool columnMajor : {false, true})
        for (const bool float64 : {false, true}) {
          ArrayFormat f;
          f.encoding = encoding;
          f.big = big;
          f.columnMajor = columnMajor;
          f.float64 = float64;
          SCOPED_TRACE(std::string(encoding) + (big ? " big" : " little") + (columnMajor ? " column" : " row") +
                       (float64 ? " float64" : " float32"));
          const SurfaceMesh m = readSurfaceMesh(write("lh.pial.surf.gii", giftiSurface(f)));
          expectPyramid(m);
          EXPECT_EQ(m.format, "gifti");
          EXPECT_EQ(m.anatomicalStructure, "CortexLeft");
          EXPECT_FALSE(m.coordinates.hasTransform);
        }
}

TEST_F(CorticalFiles, GiftiCoordinateSystemIsKept) {
  const std::string transform =
      "<CoordinateSystemTransformMatrix><DataSpace><![CDATA[NIFTI_XFORM_UNKNOWN]]></DataSpace>"
      "<TransformedSpace>NIFTI_XFORM_SCANNER_ANAT</TransformedSpace>"
      "<MatrixData>1 0 0 2.5\n0 1 0 -3\n0 0 1 4\n0 0 0 1</MatrixData></CoordinateSystemTransformMatrix>";
  const SurfaceMesh m = readGiftiSurface(write("s.surf.gii", giftiSurface({}, transform)));
  EXPECT_EQ(m.coordinates.space, "NIFTI_XFORM_UNKNOWN");
  EXPECT_EQ(m.coordinates.transformedSpace, "NIFTI_XFORM_SCANNER_ANAT");
  ASSERT_TRUE(m.coordinates.hasTransform);
  EXPECT_EQ(m.coordinates.transform[3], 2.5);
  EXPECT_EQ(m.coordinates.transform[7], -3.0);
  EXPECT_EQ(m.coordinates.transform[11], 4.0);
}

TEST_F(CorticalFiles, FreeSurferSurfaceWithAndWithoutVolumeGeometry) {
  SurfaceMesh m = readSurfaceMesh(write("lh.white", freeSurferSurface()));
  expectPyramid(m);
  EXPECT_EQ(m.coordinates.space, "tkr-RAS");
  EXPECT_FALSE(m.coordinates.hasTransform);
  EXPECT_EQ(m.anatomicalStructure, "CortexLeft");
  std::string footer;
  put(footer, std::int32_t{2}, true);
  put(footer, std::int32_t{0}, true);
  put(footer, std::int32_t{20}, true);
  footer +=
      "valid = 1  # volume info valid\nfilename = orig.mgz\nvolume = 256 256 256\nvoxelsize = 1 1 1\n"
      "xras   = -1 0 0\nyras   = 0 0 -1\nzras   = 0 1 0\ncras   = 1.5 -2 30\n";
  // Any name: a FreeSurfer surface is told by its magic number.
  m = readSurfaceMesh(write("pial_surface", freeSurferSurface(footer)));
  ASSERT_TRUE(m.coordinates.hasTransform);
  EXPECT_EQ(m.coordinates.transformedSpace, "scanner RAS");
  const std::array<double, 16> expected{1, 0, 0, 1.5, 0, 1, 0, -2, 0, 0, 1, 30, 0, 0, 0, 1};
  for (int i = 0; i < 16; ++i) EXPECT_NEAR(m.coordinates.transform[i], expected[i], 1e-12) << i;
  EXPECT_TRUE(m.anatomicalStructure.empty());
  // useRealRAS 1: the coordinates are scanner RAS already.
  std::string real;
  put(real, std::int32_t{2}, true);
  put(real, std::int32_t{1}, true);
  m = readSurfaceMesh(write("rh.pial", freeSurferSurface(real)));
  EXPECT_EQ(m.coordinates.space, "scanner RAS");
  EXPECT_FALSE(m.coordinates.hasTransform);
  EXPECT_EQ(m.anatomicalStructure, "CortexRight");
}

TEST_F(CorticalFiles, PerVertexValuesFromCurvMghMgzAndGifti) {
  const std::vector<float> values{0.5f, -1.25f, 3.0f, 0.0f, 7.75f};
  std::string curv = "\xFF\xFF\xFF";
  put(curv, std::int32_t{5}, true);
  put(curv, std::int32_t{4}, true);
  put(curv, std::int32_t{1}, true);
  for (const float v : values) put(curv, v, true);
  std::string old = "\x00\x00\x05\x00\x00\x04";
  old = std::string("\x00\x00\x05\x00\x00\x04", 6);
  for (const float v : values) put(old, static_cast<std::int16_t>(std::lround(v * 100)), true);
  std::string mgh;
  for (const std::int32_t x : {1, 5, 1, 1, 1, 3, 0}) put(mgh, x, true);
  mgh.resize(284, '\0');
  for (const float v : values) put(mgh, v, true);
  mgh += "trailing tags";
  const std::string gifti = "<GIFTI Version=\"1.0\">" +
                            dataArray("NIFTI_INTENT_SHAPE",
                                      std::vector<double>(values.begin(), values.end()), 5, 1, false, {}) +
                            "</GIFTI>";
  for (const auto& [name, bytes] :
       std::vector<std::pair<std::string, std::string>>{{"lh.thickness", curv},
                                                        {"lh.old", old},
                                                        {"v.mgh", mgh},
                                                        {"v.mgz", gzipCompressed(mgh)},
                                                        {"v.shape.gii", gifti}}) {
    SCOPED_TRACE(name);
    const std::vector<double> read = readVertexValues(write(name, bytes), 5);
    ASSERT_EQ(read.size(), 5u);
    for (std::size_t v = 0; v < 5; ++v) EXPECT_EQ(read[v], values[v]);
    const std::string path = (folder_ / name).string();  // a structured binding cannot be captured (C++17)
    EXPECT_NE(errorOf([&] { readVertexValues(path, 6); }).find("for a surface of 6 vertices"),
              std::string::npos);
  }
}

TEST_F(CorticalFiles, AnnotationsWithBothColourTablesLabelsAndGiftiLabels) {
  // Vertices 0, 1 in "precentral" (colour 10,20,30), 2 in "lingual"
  // (40,50,60), 3 and 4 in no entry.
  auto annotation = [](bool oldTable) {
    std::string b;
    put(b, std::int32_t{5}, true);
    const std::int32_t colours[5] = {10 + 20 * 256 + 30 * 65536, 10 + 20 * 256 + 30 * 65536,
                                     40 + 50 * 256 + 60 * 65536, 0, 77};
    for (std::int32_t v = 0; v < 5; ++v) {
      put(b, v, true);
      put(b, colours[v], true);
    }
    put(b, std::int32_t{1}, true);
    auto text = [&](const std::string& t) {
      put(b, static_cast<std::int32_t>(t.size() + 1), true);
      b += t + '\0';
    };
    if (oldTable) {
      put(b, std::int32_t{2}, true);
      text("colortable.txt");
    } else {
      put(b, std::int32_t{-2}, true);
      put(b, std::int32_t{5}, true);
      text("colortable.txt");
      put(b, std::int32_t{2}, true);
    }
    const char* names[2] = {"precentral", "lingual"};
    const int rgb[2][3] = {{10, 20, 30}, {40, 50, 60}};
    for (int e = 0; e < 2; ++e) {
      if (!oldTable) put(b, std::int32_t{e + 3}, true);
      text(names[e]);
      for (int c = 0; c < 3; ++c) put(b, std::int32_t{rgb[e][c]}, true);
      put(b, std::int32_t{0}, true);
    }
    return b;
  };
  for (const bool oldTable : {false, true}) {
    const VertexRegions r = readVertexRegions(write("lh.aparc.annot", annotation(oldTable)), 5);
    const std::int32_t first = oldTable ? 0 : 3;
    EXPECT_EQ(r.key, (std::vector<std::int32_t>{first, first, first + 1, -1, -1}));
    EXPECT_EQ(r.name.at(first), "precentral");
    EXPECT_EQ(regionVertices(r, "lingual", "a"), (std::vector<VertexId>{2}));
    EXPECT_NE(errorOf([&] { regionVertices(r, "insula", "lh.aparc.annot"); })
                  .find("no region named \"insula\" (the file names precentral, lingual)"),
              std::string::npos);
  }
  const VertexRegions label = readVertexRegions(
      write("lh.V1.label", "#!ascii label , from subject\n2\n4 1.0 2.0 3.0 0.5\n1 0 0 0 0\n"), 5);
  EXPECT_EQ(label.key, (std::vector<std::int32_t>{-1, 1, -1, -1, 1}));
  EXPECT_EQ(label.name.at(1), "lh.V1");
  const std::string labelGifti =
      "<GIFTI Version=\"1.0\"><LabelTable><Label Key=\"0\" Red=\"1\">unknown</Label>"
      "<Label Key=\"7\" Red=\"0.5\" Green=\"0\" Blue=\"0\" Alpha=\"1\"><![CDATA[V1 &amp; V2]]></Label></LabelTable>" +
      dataArray("NIFTI_INTENT_LABEL", {0, 7, 7, 0, 0}, 5, 1, true, {}) + "</GIFTI>";
  const VertexRegions g = readVertexRegions(write("lh.label.gii", labelGifti), 5);
  EXPECT_EQ(g.key, (std::vector<std::int32_t>{0, 7, 7, 0, 0}));
  EXPECT_EQ(g.name.at(7), "V1 &amp; V2");  // CDATA is taken literally
}

TEST_F(CorticalFiles, WrittenValuesReadBack) {
  SurfaceMesh mesh = readSurfaceMesh(write("lh.pial", freeSurferSurface()));
  const std::vector<double> d{0.0, 1.5, std::nan(""), 2.25, 1e30};
  for (const char* name : {"d.shape.gii", "d.func.gii", "lh.distance", "d.curv"}) {
    SCOPED_TRACE(name);
    const std::string path = (folder_ / name).string();
    writeSurfaceDistances(path, path, mesh, d);
    if (std::string(name).find(".gii") != std::string::npos) {
      // Compressed, as NiBabel and Connectome Workbench write GIfTI data.
      std::ifstream in(path, std::ios::binary);
      const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      EXPECT_NE(text.find("Encoding=\"GZipBase64Binary\""), std::string::npos) << text;
    }
    const std::vector<double> back = readVertexValues(path, 5);
    for (std::size_t v = 0; v < 5; ++v) {
      if (std::isnan(d[v])) EXPECT_TRUE(std::isnan(back[v]));
      else EXPECT_EQ(back[v], static_cast<float>(d[v]));
    }
  }
  EXPECT_EQ(vertexValuesFormatOf("lh.pial.surf.gii"), VertexValuesFormat::None);
  EXPECT_EQ(vertexValuesFormatOf("lh.d.ply"), VertexValuesFormat::None);
  EXPECT_EQ(vertexValuesFormatOf("lh.d"), VertexValuesFormat::FreeSurferCurv);
  EXPECT_TRUE(isSurfaceOutputPath("x.shape.gii"));
  EXPECT_FALSE(isSurfaceOutputPath("x.label.gii"));
}

TEST_F(CorticalFiles, HostileGiftiFilesAreOneLineErrors) {
  ArrayFormat gz;
  gz.encoding = "GZipBase64Binary";
  const std::string good = giftiSurface(gz);
  auto with = [&](const std::string& from, const std::string& to) {
    std::string s = good;
    const std::size_t at = s.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return s.replace(at, from.size(), to);
  };
  std::string deep = "<GIFTI>";
  for (int i = 0; i < 100000; ++i) deep += "<a>";
  const std::vector<std::pair<std::string, std::string>> cases{
      {good.substr(0, good.rfind("</GIFTI>")), "<GIFTI> is not closed"},
      {with("Dim0=\"5\"", "Dim0=\"2147483648\""), "more than"},
      {with("Dim0=\"5\"", "Dim0=\"100000000\""), "cannot hold"},
      {with("Dim0=\"5\"", "Dim0=\"-5\""), "Dim0 must be a count"},
      {with("Dim0=\"5\"", "Dim0=\"6\""), "bytes expected"},
      {with("Encoding=\"GZipBase64Binary\"", "Encoding=\"ExternalFileBinary\""), "external file"},
      {with("NIFTI_TYPE_FLOAT32", "NIFTI_TYPE_COMPLEX64"), "unsupported DataType"},
      {with("<Data>", "<Data>&xxe;"), "unknown entity &xxe;"},
      {with("<Data>", "<Data>!!!"), "not valid base64"},
      {with("\"NIFTI_INTENT_TRIANGLE\"", "\"NIFTI_INTENT_NONE\""), "not a GIfTI surface"},
      {with("<GIFTI", "<NIFTI"), "</GIFTI> closes <NIFTI>"},
      {deep, "nested deeper than 64"},
      {"", "no root element"},
  };
  for (const auto& [bytes, problem] : cases) {
    SCOPED_TRACE(problem);
    const std::string path = write("bad.surf.gii", bytes);
    const std::string message = errorOf([&] { readSurfaceMesh(path); });
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(problem), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
  // Triangle indices out of range: ASCII, so that the text says it.
  ArrayFormat ascii;
  ascii.encoding = "ASCII";
  std::string s = giftiSurface(ascii);
  s.replace(s.rfind("4.000000"), 8, "9.000000");
  EXPECT_NE(errorOf([&] { readSurfaceMesh(write("b.surf.gii", s)); }).find("refers to vertex 9"), std::string::npos);
}

TEST_F(CorticalFiles, HostileFreeSurferFilesAreOneLineErrors) {
  const std::string good = freeSurferSurface();
  std::string huge = good;
  huge.replace(huge.find("\n\n") + 2, 4, std::string("\x7F\xFF\xFF\xFF", 4));
  std::string badIndex = good;
  badIndex.replace(badIndex.size() - 4, 4, std::string("\x00\x00\x00\x09", 4));
  std::string quad = good;
  quad[2] = '\xFF';
  const std::vector<std::pair<std::string, std::string>> cases{
      {good.substr(0, 60), "the file ends in the vertices"},
      {good.substr(0, good.size() - 2), "the file ends in the triangles"},
      {huge, "the file ends in the vertices"},
      {badIndex, "refers to vertex 9"},
      {quad, "quadrangle surface"},
      {"\xFF\xFF\xFE", "ends in the creation line"},
  };
  for (const auto& [bytes, problem] : cases) {
    SCOPED_TRACE(problem);
    const std::string path = write("lh.bad", bytes);
    const std::string message = errorOf([&] { readSurfaceMesh(path); });
    EXPECT_EQ(message.rfind(path + ": ", 0), 0u) << message;
    EXPECT_NE(message.find(problem), std::string::npos) << message;
  }
  // An annotation claiming 2^31 - 1 vertices, a curv file with 2 values per
  // vertex, an .mgz claiming more voxels than it inflates to.
  std::string annot;
  put(annot, std::int32_t{5}, true);
  put(annot, std::int32_t{0}, true);
  EXPECT_NE(errorOf([&] { readVertexRegions(write("x.annot", annot), 5); }).find("ends in the vertices' colours"),
            std::string::npos);
  std::string curv = "\xFF\xFF\xFF";
  for (const std::int32_t x : {5, 4, 2}) put(curv, x, true);
  EXPECT_NE(errorOf([&] { readVertexValues(write("lh.curv", curv), 5); }).find("2 values per vertex"),
            std::string::npos);
  std::string mgh;
  for (const std::int32_t x : {1, 5, 1, 1, 1, 3, 0}) put(mgh, x, true);
  mgh.resize(284, '\0');
  EXPECT_NE(errorOf([&] { readVertexValues(write("v.mgz", gzipCompressed(mgh)), 5); }).find("ends in the values"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { readVertexValues(write("v.mgz", "\x1F\x8Bnot gzip"), 5); }).find("not a valid"),
            std::string::npos);
  EXPECT_NE(errorOf([&] { readVertexRegions(write("lh.x.label", "#!ascii\n3\n1 0 0 0 0\n"), 5); })
                .find("ends after 1 of 3 vertices"),
            std::string::npos);
}

TEST_F(CorticalFiles, OnlyRegularFilesAreRead) {
  const std::string fifo = (folder_ / "lh.pial").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  EXPECT_NE(errorOf([&] { readSurfaceMesh(fifo); }).find("FIFO"), std::string::npos);
  EXPECT_FALSE(isFreeSurferSurfaceFile(fifo));
  const std::string gii = (folder_ / "x.shape.gii").string();
  ASSERT_EQ(::mkfifo(gii.c_str(), 0600), 0);
  EXPECT_NE(errorOf([&] { readVertexValues(gii, 5); }).find("FIFO"), std::string::npos);
}

}  // namespace
}  // namespace stvd::surface_io
