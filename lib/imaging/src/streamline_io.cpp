#include "stvd/imaging/streamline_io.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>

#include "stvd/errors.hpp"
#include "stvd/imaging/detail/image_output.hpp"
#include "stvd/system/files/file_contents.hpp"
#include "stvd/system/files/output_transaction.hpp"

namespace stvd::imaging {
namespace {

Vec3d lpsToRas(Vec3d p) { return {-p.x, -p.y, p.z}; }

std::string lowerCase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void checkSet(const std::string& path, const StreamlineSet& set, StreamlineFormat format) {
  if (set.pointValueNames.size() != set.pointValues.size() || set.lineValueNames.size() != set.lineValues.size())
    throw ImageIoError(path, "streamline values and their names differ in number");
  if (set.pointValueNames.size() > 10 || set.lineValueNames.size() > 10)
    throw ImageIoError(path, "more than 10 per-point or per-line values");
  for (const auto& values : set.pointValues) {
    if (values.size() != set.lines.size()) throw ImageIoError(path, "per-point values for a different number of lines");
    for (std::size_t l = 0; l < values.size(); ++l)
      if (values[l].size() != set.lines[l].size())
        throw ImageIoError(path, "per-point values for a different number of points");
  }
  for (const auto& values : set.lineValues)
    if (values.size() != set.lines.size()) throw ImageIoError(path, "per-line values for a different number of lines");
  auto checkName = [&](const std::string& name) {
    if (name.empty() || name.size() > 19 || name.find_first_of(" \t\n:") != std::string::npos)
      throw ImageIoError(path, "value name '" + name + "' is empty, longer than 19 characters or has a space or ':'");
  };
  for (const auto& n : set.pointValueNames) checkName(n);
  for (const auto& n : set.lineValueNames) checkName(n);
  if (format == StreamlineFormat::Trk)
    for (std::size_t a = 0; a < 3; ++a)
      if (set.geometry.size[a] > 32767) throw ImageIoError(path, "the reference grid is too large for a .trk header");
}

template <class T>
void put(std::string& buffer, std::size_t offset, T value) {
  std::memcpy(&buffer[offset], &value, sizeof value);  // x86-64 and ARM64 Linux: little-endian
}

void appendFloat(std::string& out, float value) {
  char bytes[4];
  std::memcpy(bytes, &value, 4);
  out.append(bytes, 4);
}

std::string tckContents(const StreamlineSet& set) {
  std::ostringstream header;
  header << "mrtrix tracks\n";
  header << "datatype: Float32LE\n";
  header << "count: " << set.lines.size() << "\n";
  header << "total_count: " << set.lines.size() << "\n";
  header.precision(9);
  for (std::size_t v = 0; v < set.lineValueNames.size(); ++v) {
    header << set.lineValueNames[v] << ":";
    for (float x : set.lineValues[v]) header << " " << x;
    header << "\n";
  }
  // "file: . OFFSET" names where the data start; the offset counts its own
  // digits, so it is found by iteration.
  const std::string head = header.str();
  std::size_t offset = head.size() + 32;
  std::string text;
  for (int round = 0; round < 4; ++round) {
    text = head + "file: . " + std::to_string(offset) + "\nEND\n";
    if (text.size() <= offset) break;
    offset = text.size();
  }
  text.resize(offset, '\0');
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  for (const auto& line : set.lines) {
    for (const Vec3d& p : line) {
      const Vec3d r = lpsToRas(p);
      appendFloat(text, static_cast<float>(r.x));
      appendFloat(text, static_cast<float>(r.y));
      appendFloat(text, static_cast<float>(r.z));
    }
    for (int c = 0; c < 3; ++c) appendFloat(text, nan);
  }
  for (int c = 0; c < 3; ++c) appendFloat(text, inf);
  return text;
}

std::string trkContents(const StreamlineSet& set) {
  const GridGeometry& g = set.geometry;
  std::string out(1000, '\0');
  std::memcpy(&out[0], "TRACK", 5);
  for (int a = 0; a < 3; ++a) {
    put<std::int16_t>(out, 6 + 2 * a, static_cast<std::int16_t>(g.size[a]));
    put<float>(out, 12 + 4 * a, static_cast<float>(g.spacing[a]));
  }
  put<std::int16_t>(out, 36, static_cast<std::int16_t>(set.pointValueNames.size()));
  for (std::size_t s = 0; s < set.pointValueNames.size(); ++s)
    std::memcpy(&out[38 + 20 * s], set.pointValueNames[s].data(), set.pointValueNames[s].size());
  put<std::int16_t>(out, 238, static_cast<std::int16_t>(set.lineValueNames.size()));
  for (std::size_t s = 0; s < set.lineValueNames.size(); ++s)
    std::memcpy(&out[240 + 20 * s], set.lineValueNames[s].data(), set.lineValueNames[s].size());
  const std::array<double, 16> affine = voxelToRas(g);
  for (int e = 0; e < 16; ++e) put<float>(out, 440 + 4 * e, static_cast<float>(affine[e]));
  const std::string order = rasAxisCodes(g);
  std::memcpy(&out[948], order.data(), 3);
  put<std::int32_t>(out, 988, static_cast<std::int32_t>(set.lines.size()));
  put<std::int32_t>(out, 992, 2);
  put<std::int32_t>(out, 996, 1000);
  for (std::size_t l = 0; l < set.lines.size(); ++l) {
    const auto& line = set.lines[l];
    char count[4];
    const std::int32_t n = static_cast<std::int32_t>(line.size());
    std::memcpy(count, &n, 4);
    out.append(count, 4);
    for (std::size_t p = 0; p < line.size(); ++p) {
      // TrackVis "voxmm": the voxel corner is 0, so a voxel centre sits at
      // (index + 0.5) * voxel size.
      const Vec3d c = g.physicalPointToIndex(line[p]);
      appendFloat(out, static_cast<float>((c.x + 0.5) * g.spacing[0]));
      appendFloat(out, static_cast<float>((c.y + 0.5) * g.spacing[1]));
      appendFloat(out, static_cast<float>((c.z + 0.5) * g.spacing[2]));
      for (const auto& values : set.pointValues) appendFloat(out, values[l][p]);
    }
    for (const auto& values : set.lineValues) appendFloat(out, values[l]);
  }
  return out;
}

std::string vtkContents(const StreamlineSet& set) {
  std::ostringstream out;
  out.precision(9);
  std::size_t points = 0;
  for (const auto& line : set.lines) points += line.size();
  out << "# vtk DataFile Version 3.0\n";
  out << "stvd geodesic paths SPACE=RAS (millimetres)\n";
  out << "ASCII\n";
  out << "DATASET POLYDATA\n";
  out << "POINTS " << points << " float\n";
  for (const auto& line : set.lines)
    for (const Vec3d& p : line) {
      const Vec3d r = lpsToRas(p);
      out << r.x << " " << r.y << " " << r.z << "\n";
    }
  out << "LINES " << set.lines.size() << " " << points + set.lines.size() << "\n";
  std::size_t next = 0;
  for (const auto& line : set.lines) {
    out << line.size();
    for (std::size_t p = 0; p < line.size(); ++p) out << " " << next++;
    out << "\n";
  }
  if (!set.lineValueNames.empty()) {
    out << "CELL_DATA " << set.lines.size() << "\n";
    for (std::size_t v = 0; v < set.lineValueNames.size(); ++v) {
      out << "SCALARS " << set.lineValueNames[v] << " float 1\nLOOKUP_TABLE default\n";
      for (float x : set.lineValues[v]) out << x << "\n";
    }
  }
  if (!set.pointValueNames.empty()) {
    out << "POINT_DATA " << points << "\n";
    for (std::size_t v = 0; v < set.pointValueNames.size(); ++v) {
      out << "SCALARS " << set.pointValueNames[v] << " float 1\nLOOKUP_TABLE default\n";
      for (const auto& line : set.pointValues[v])
        for (float x : line) out << x << "\n";
    }
  }
  return out.str();
}

}  // namespace

std::optional<StreamlineFormat> streamlineFormatOf(const std::string& path) {
  const std::string p = lowerCase(path);
  if (endsWith(p, ".tck")) return StreamlineFormat::Tck;
  if (endsWith(p, ".trk")) return StreamlineFormat::Trk;
  if (endsWith(p, ".vtk")) return StreamlineFormat::Vtk;
  return std::nullopt;
}

std::array<double, 16> voxelToRas(const GridGeometry& g) {
  std::array<double, 16> m{};
  const double flip[3] = {-1.0, -1.0, 1.0};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[4 * r + c] = flip[r] * g.direction[3 * r + c] * g.spacing[c];
    m[4 * r + 3] = flip[r] * g.origin[r];
  }
  m[15] = 1.0;
  return m;
}

std::string rasAxisCodes(const GridGeometry& g) {
  // Greedy assignment by the largest remaining |cosine|, as nibabel's
  // io_orientation does for an orthonormal matrix.
  double d[3][3];
  const double flip[3] = {-1.0, -1.0, 1.0};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) d[r][c] = flip[r] * g.direction[3 * r + c];
  const char positive[3] = {'R', 'A', 'S'}, negative[3] = {'L', 'P', 'I'};
  std::string code = "???";
  bool rowUsed[3] = {false, false, false}, columnUsed[3] = {false, false, false};
  for (int round = 0; round < 3; ++round) {
    int bestRow = -1, bestColumn = -1;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        if (!rowUsed[r] && !columnUsed[c] && (bestRow < 0 || std::abs(d[r][c]) > std::abs(d[bestRow][bestColumn]))) {
          bestRow = r;
          bestColumn = c;
        }
    rowUsed[bestRow] = columnUsed[bestColumn] = true;
    code[bestColumn] = d[bestRow][bestColumn] > 0 ? positive[bestRow] : negative[bestRow];
  }
  return code;
}

namespace {

/// The bytes of the file; throws ImageIoError for an unknown extension or an
/// inconsistent set.
std::string streamlineFileContents(const std::string& path, const StreamlineSet& set) {
  const std::optional<StreamlineFormat> format = streamlineFormatOf(path);
  if (!format) throw ImageIoError(path, "unknown streamline format; use .tck, .trk or .vtk");
  checkSet(path, set, *format);
  std::string contents;
  switch (*format) {
    case StreamlineFormat::Tck: contents = tckContents(set); break;
    case StreamlineFormat::Trk: contents = trkContents(set); break;
    case StreamlineFormat::Vtk: contents = vtkContents(set); break;
  }
  return contents;
}

}  // namespace

void writeStreamlines(const std::string& path, const StreamlineSet& set) {
  const std::string contents = streamlineFileContents(path, set);
  detail::writeAtomically(path, [&](const std::string& staging) { files::writeFileContents(staging, contents); });
}

void writeStreamlines(files::OutputTransaction& outputs, const std::string& path, const StreamlineSet& set) {
  const std::string contents = streamlineFileContents(path, set);
  outputs.write(path, [&](const std::string& staging) { files::writeFileContents(staging, contents); });
}

}  // namespace stvd::imaging
