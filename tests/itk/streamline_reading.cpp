#include "streamline_reading.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace stvd::testing {
namespace {

// Prints one record per line: "P line x y z" for points, "S name line value"
// for per-streamline data, "Q name line point value" for per-point data and
// "H key value" for header entries.
const char* kLoader = R"PY(
import sys
import numpy as np
import nibabel as nib
f = nib.streamlines.load(sys.argv[1])
t = f.tractogram
for key in ('voxel_order', 'count', 'datatype'):
    if key in f.header:
        v = f.header[key]
        v = v.decode() if isinstance(v, bytes) else v
        print('H', key, str(v).replace(' ', '_'))
for key, value in f.header.items():
    if isinstance(value, str) and key not in ('voxel_order', 'count', 'datatype'):
        print('H', key, value.replace(' ', '_'))
for i, s in enumerate(t.streamlines):
    for p in np.asarray(s, dtype=np.float64):
        print('P', i, repr(p[0]), repr(p[1]), repr(p[2]))
for name, values in t.data_per_streamline.items():
    for i, v in enumerate(np.asarray(values, dtype=np.float64).reshape(len(t.streamlines), -1)):
        print('S', name, i, repr(v[0]))
for name, values in t.data_per_point.items():
    for i, s in enumerate(values):
        for j, v in enumerate(np.asarray(s, dtype=np.float64).reshape(-1)):
            print('Q', name, i, j, repr(v))
)PY";

std::string quote(const std::string& word) {
  std::string q = "'";
  for (char c : word) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace

LoadedStreamlines loadWithNibabel(const std::string& path) {
  const fs::path base = fs::temp_directory_path() / ("stvd_nibabel_" + std::to_string(::getpid()));
  const fs::path script = base.string() + ".py", out = base.string() + ".out", err = base.string() + ".err";
  {
    std::ofstream s(script);
    s << kLoader;
  }
  const std::string command = "/usr/bin/python3 " + quote(script.string()) + " " + quote(path) + " >" +
                              quote(out.string()) + " 2>" + quote(err.string()) + " </dev/null";
  const int status = std::system(command.c_str());
  LoadedStreamlines loaded;
  const std::string text = slurp(out);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) loaded.error = "python failed: " + slurp(err);
  std::error_code ec;
  fs::remove(script, ec);
  fs::remove(out, ec);
  fs::remove(err, ec);
  std::istringstream lines(text);
  std::string record;
  while (std::getline(lines, record)) {
    std::istringstream r(record);
    std::string kind;
    r >> kind;
    if (kind == "P") {
      std::size_t i;
      Vec3d p;
      r >> i >> p.x >> p.y >> p.z;
      if (loaded.lines.size() <= i) loaded.lines.resize(i + 1);
      loaded.lines[i].push_back(p);
    } else if (kind == "S") {
      std::string name;
      std::size_t i;
      double v;
      r >> name >> i >> v;
      auto& values = loaded.perLine[name];
      if (values.size() <= i) values.resize(i + 1);
      values[i] = v;
    } else if (kind == "Q") {
      std::string name;
      std::size_t i, j;
      double v;
      r >> name >> i >> j >> v;
      auto& values = loaded.perPoint[name];
      if (values.size() <= i) values.resize(i + 1);
      if (values[i].size() <= j) values[i].resize(j + 1);
      values[i][j] = v;
    } else if (kind == "H") {
      std::string key, value;
      r >> key >> value;
      loaded.header[key] = value;
    }
  }
  return loaded;
}

LoadedStreamlines loadLegacyVtk(const std::string& path) {
  LoadedStreamlines loaded;
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  if (line.rfind("# vtk DataFile", 0) != 0) {
    loaded.error = "not a legacy VTK file";
    return loaded;
  }
  std::getline(in, line);  // title
  loaded.header["title"] = line;
  std::string word;
  std::vector<Vec3d> points;
  std::vector<std::vector<std::size_t>> cells;
  std::string section;
  std::size_t sectionCount = 0;
  while (in >> word) {
    if (word == "ASCII" || word == "DATASET" || word == "POLYDATA" || word == "LOOKUP_TABLE") {
      if (word == "LOOKUP_TABLE") in >> word;
      continue;
    }
    if (word == "POINTS") {
      std::size_t n;
      in >> n >> word;
      points.resize(n);
      for (auto& p : points) in >> p.x >> p.y >> p.z;
    } else if (word == "LINES") {
      std::size_t n, size;
      in >> n >> size;
      cells.resize(n);
      for (auto& c : cells) {
        std::size_t count;
        in >> count;
        c.resize(count);
        for (auto& index : c) in >> index;
      }
    } else if (word == "CELL_DATA" || word == "POINT_DATA") {
      section = word;
      in >> sectionCount;
    } else if (word == "SCALARS") {
      std::string name, type;
      int components;
      in >> name >> type >> components >> word >> word;  // LOOKUP_TABLE default
      if (section == "CELL_DATA") {
        auto& values = loaded.perLine[name];
        values.resize(sectionCount);
        for (auto& v : values) in >> v;
      } else {
        auto& values = loaded.perPoint[name];
        values.resize(cells.size());
        for (std::size_t c = 0; c < cells.size(); ++c) {
          values[c].resize(cells[c].size());
          for (auto& v : values[c]) in >> v;
        }
      }
    } else {
      loaded.error = "unexpected word '" + word + "'";
      return loaded;
    }
  }
  for (const auto& c : cells) {
    loaded.lines.emplace_back();
    for (std::size_t index : c) loaded.lines.back().push_back(points.at(index));
  }
  return loaded;
}

}  // namespace stvd::testing
