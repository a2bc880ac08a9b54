// Reader of TetGen's .node, .ele and .face files.
#include <sys/stat.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "stvd/system/files/regular_file.hpp"
#include "stvd/tetmesh/tet_mesh.hpp"

namespace stvd::tetmesh {
namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// The data lines of a TetGen file, comments and blank lines dropped, each
/// split into tokens and remembering its line number for messages.
class TetGenFile {
 public:
  explicit TetGenFile(std::string path) : path_(std::move(path)) {
    // A regular file only: a FIFO or a device named like a mesh file would
    // block the reader or never end.
    std::istringstream in;
    try {
      in.str(files::readRegularFile(path_));
    } catch (const files::InputFileError& e) {
      throw TetMeshError(path_ + ": cannot open the file" + (e.problem() == "no such file" ? "" : " (" + e.problem() + ")"));
    }
    std::string line;
    std::size_t number = 0;
    while (std::getline(in, line)) {
      ++number;
      const std::size_t hash = line.find('#');
      if (hash != std::string::npos) line.resize(hash);
      std::istringstream tokens(line);
      std::vector<std::string> row;
      for (std::string t; tokens >> t;) row.push_back(t);
      if (!row.empty()) {
        rows_.push_back(std::move(row));
        lineNumbers_.push_back(number);
      }
    }
    if (in.bad()) throw TetMeshError(path_ + ": read error");
  }

  const std::string& path() const { return path_; }
  std::size_t rowCount() const { return rows_.size(); }
  const std::vector<std::string>& row(std::size_t r) const { return rows_[r]; }

  [[noreturn]] void fail(std::size_t r, const std::string& what) const {
    if (r < lineNumbers_.size())
      throw TetMeshError(path_ + ":" + std::to_string(lineNumbers_[r]) + ": " + what);
    throw TetMeshError(path_ + ": " + what);
  }

  std::int64_t integer(std::size_t r, std::size_t column, const char* what) const {
    const std::string& t = token(r, column, what);
    errno = 0;
    char* end = nullptr;
    const long long value = std::strtoll(t.c_str(), &end, 10);
    if (errno != 0 || end == t.c_str() || *end != '\0')
      fail(r, std::string(what) + " '" + t + "' is not an integer");
    return value;
  }
  double real(std::size_t r, std::size_t column, const char* what) const {
    const std::string& t = token(r, column, what);
    errno = 0;
    char* end = nullptr;
    const double value = std::strtod(t.c_str(), &end);
    if (end == t.c_str() || *end != '\0') fail(r, std::string(what) + " '" + t + "' is not a number");
    if (!std::isfinite(value)) fail(r, std::string(what) + " '" + t + "' is not finite");
    return value;
  }
  /// Data rows after the header: exactly `count` of them, each with
  /// `columns` tokens.
  void expectRows(std::size_t count, std::size_t columns, const char* what) const {
    if (rowCount() - 1 < count)
      fail(rowCount(), "the header announces " + std::to_string(count) + " " + what + " but the file has " +
                           std::to_string(rowCount() - 1));
    if (rowCount() - 1 > count)
      fail(count + 1, "more lines than the " + std::to_string(count) + " " + what + " the header announces");
    for (std::size_t r = 1; r <= count; ++r)
      if (row(r).size() != columns)
        fail(r, "expected " + std::to_string(columns) + " values, found " + std::to_string(row(r).size()));
  }

 private:
  const std::string& token(std::size_t r, std::size_t column, const char* what) const {
    if (column >= rows_[r].size()) fail(r, std::string("missing ") + what);
    return rows_[r][column];
  }

  std::string path_;
  std::vector<std::vector<std::string>> rows_;
  std::vector<std::size_t> lineNumbers_;
};

std::size_t nonNegativeCount(const TetGenFile& f, std::size_t column, const char* what, std::int64_t limit) {
  const std::int64_t n = f.integer(0, column, what);
  if (n < 0 || n > limit) f.fail(0, std::string(what) + " " + std::to_string(n) + " is out of range");
  return static_cast<std::size_t>(n);
}

constexpr std::int64_t kMaxCount = std::int64_t{1} << 31;  // VertexId is 32-bit
constexpr std::int64_t kMaxAttributes = 1 << 16;

void readNodes(const TetGenFile& f, TetMesh& mesh) {
  if (f.rowCount() == 0) f.fail(0, "empty file (expected the header '<points> 3 <attributes> <markers>')");
  const std::size_t n = nonNegativeCount(f, 0, "point count", kMaxCount - 2);
  if (n == 0) f.fail(0, "no points (a .node file with 0 points defers to a .poly file, which is not read here)");
  const std::int64_t dimension = f.row(0).size() > 1 ? f.integer(0, 1, "dimension") : 3;
  if (dimension != 3) f.fail(0, "dimension " + std::to_string(dimension) + " (only 3 is supported)");
  mesh.pointAttributeCount = f.row(0).size() > 2 ? nonNegativeCount(f, 2, "attribute count", kMaxAttributes) : 0;
  const std::int64_t markers = f.row(0).size() > 3 ? f.integer(0, 3, "boundary marker flag") : 0;
  if (markers != 0 && markers != 1) f.fail(0, "boundary marker flag must be 0 or 1");
  if (f.row(0).size() > 4) f.fail(0, "the header has more than 4 values");
  const std::size_t columns = 4 + mesh.pointAttributeCount + static_cast<std::size_t>(markers);
  f.expectRows(n, columns, "points");

  const std::int64_t first = f.integer(1, 0, "point number");
  if (first != 0 && first != 1) f.fail(1, "the first point is numbered " + std::to_string(first) + " (expected 0 or 1)");
  mesh.firstIndex = static_cast<int>(first);
  mesh.points.resize(n);
  mesh.pointAttributes.resize(n * mesh.pointAttributeCount);
  if (markers) mesh.pointMarkers.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = i + 1;
    const std::int64_t number = f.integer(r, 0, "point number");
    if (number != first + static_cast<std::int64_t>(i))
      f.fail(r, "point number " + std::to_string(number) + " where " + std::to_string(first + i) +
                    " was expected (points must be numbered consecutively)");
    mesh.points[i] = {f.real(r, 1, "x"), f.real(r, 2, "y"), f.real(r, 3, "z")};
    for (std::size_t a = 0; a < mesh.pointAttributeCount; ++a)
      mesh.pointAttributes[i * mesh.pointAttributeCount + a] = f.real(r, 4 + a, "attribute");
    if (markers) mesh.pointMarkers[i] = f.integer(r, 4 + mesh.pointAttributeCount, "boundary marker");
  }
}

/// A corner index in the file's numbering turned 0-based, or a failure.
VertexId corner(const TetGenFile& f, std::size_t r, std::size_t column, const TetMesh& mesh, const char* element) {
  const std::int64_t number = f.integer(r, column, "corner");
  const std::int64_t index = number - mesh.firstIndex;
  if (index < 0 || index >= static_cast<std::int64_t>(mesh.points.size()))
    f.fail(r, std::string(element) + " corner " + std::to_string(number) + " is out of range (points are numbered " +
                  std::to_string(mesh.firstIndex) + ".." +
                  std::to_string(mesh.firstIndex + static_cast<std::int64_t>(mesh.points.size()) - 1) + ")");
  return static_cast<VertexId>(index);
}

void checkElementNumber(const TetGenFile& f, std::size_t r, std::size_t i, const TetMesh& mesh, const char* element) {
  const std::int64_t number = f.integer(r, 0, "number");
  const std::int64_t expected = mesh.firstIndex + static_cast<std::int64_t>(i);
  if (number != expected)
    f.fail(r, std::string(element) + " number " + std::to_string(number) + " where " + std::to_string(expected) +
                  " was expected (numbered consecutively from the .node file's first number)");
}

void readTets(const TetGenFile& f, TetMesh& mesh) {
  if (f.rowCount() == 0) f.fail(0, "empty file (expected the header '<tetrahedra> <4 or 10> <attributes>')");
  const std::size_t n = nonNegativeCount(f, 0, "tetrahedron count", kMaxCount);
  if (n == 0) f.fail(0, "no tetrahedra");
  const std::int64_t nodes = f.row(0).size() > 1 ? f.integer(0, 1, "nodes per tetrahedron") : 4;
  if (nodes != 4 && nodes != 10) f.fail(0, "nodes per tetrahedron must be 4 or 10, not " + std::to_string(nodes));
  mesh.tetAttributeCount = f.row(0).size() > 2 ? nonNegativeCount(f, 2, "attribute count", kMaxAttributes) : 0;
  if (f.row(0).size() > 3) f.fail(0, "the header has more than 3 values");
  f.expectRows(n, 1 + static_cast<std::size_t>(nodes) + mesh.tetAttributeCount, "tetrahedra");
  mesh.tets.resize(n);
  mesh.tetAttributes.resize(n * mesh.tetAttributeCount);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = i + 1;
    checkElementNumber(f, r, i, mesh, "tetrahedron");
    // Second-order nodes (columns 5..10) are edge midpoints: the graph uses the corners.
    for (std::size_t c = 0; c < static_cast<std::size_t>(nodes); ++c) {
      const VertexId v = corner(f, r, 1 + c, mesh, "tetrahedron");
      if (c < 4) mesh.tets[i][c] = v;
    }
    for (std::size_t a = 0; a < mesh.tetAttributeCount; ++a)
      mesh.tetAttributes[i * mesh.tetAttributeCount + a] = f.real(r, 1 + nodes + a, "attribute");
  }
}

void readFaces(const TetGenFile& f, TetMesh& mesh) {
  if (f.rowCount() == 0) f.fail(0, "empty file (expected the header '<faces> <markers>')");
  const std::size_t n = nonNegativeCount(f, 0, "face count", kMaxCount);
  const std::int64_t markers = f.row(0).size() > 1 ? f.integer(0, 1, "boundary marker flag") : 0;
  if (markers != 0 && markers != 1) f.fail(0, "boundary marker flag must be 0 or 1");
  if (f.row(0).size() > 2) f.fail(0, "the header has more than 2 values");
  // TetGen 1.5 with -n appends the two adjacent tetrahedra to each face line.
  const std::size_t columns = 4 + static_cast<std::size_t>(markers);
  if (f.rowCount() - 1 != n) f.expectRows(n, columns, "faces");
  mesh.faces.resize(n);
  if (markers) mesh.faceMarkers.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t r = i + 1;
    if (f.row(r).size() != columns && f.row(r).size() != columns + 2)
      f.fail(r, "expected " + std::to_string(columns) + " values, found " + std::to_string(f.row(r).size()));
    checkElementNumber(f, r, i, mesh, "face");
    for (std::size_t c = 0; c < 3; ++c) mesh.faces[i][c] = corner(f, r, 1 + c, mesh, "face");
    if (markers) mesh.faceMarkers[i] = f.integer(r, 4, "boundary marker");
  }
}

bool fileExists(const std::string& path) {
  struct stat status {};
  return ::stat(path.c_str(), &status) == 0;  // a FIFO exists too, and is refused when read
}

}  // namespace

std::string tetGenBaseName(const std::string& path) {
  for (const char* suffix : {".node", ".ele", ".face"})
    if (endsWith(path, suffix)) return path.substr(0, path.size() - std::string(suffix).size());
  return path;
}

TetMesh readTetGenMesh(const std::string& path, const TetMeshChecks& checks) {
  const std::string base = tetGenBaseName(path);
  TetMesh mesh;
  const std::string nodePath = base + ".node", elePath = base + ".ele", facePath = base + ".face";
  readNodes(TetGenFile(nodePath), mesh);
  if (!fileExists(elePath)) throw TetMeshError(elePath + ": cannot open the file (a .node file needs its .ele file)");
  readTets(TetGenFile(elePath), mesh);
  if (fileExists(facePath)) readFaces(TetGenFile(facePath), mesh);
  validateTetMesh(mesh, nodePath, elePath, checks);
  return mesh;
}

}  // namespace stvd::tetmesh
