// Reading streamline files independently of stvd's writers: .tck and .trk
// through nibabel (Debian's python3-nibabel, nibabel.streamlines.load, which
// returns RAS millimetres), legacy VTK polydata through a small parser here.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "stvd/types.hpp"

namespace stvd::testing {

struct LoadedStreamlines {
  /// Points of each line in RAS millimetres.
  std::vector<std::vector<Vec3d>> lines;
  /// Per-line values by name (nibabel's data_per_streamline, VTK CELL_DATA).
  std::map<std::string, std::vector<double>> perLine;
  /// Per-point values by name, [line][point] (data_per_point, POINT_DATA).
  std::map<std::string, std::vector<std::vector<double>>> perPoint;
  /// Header entries nibabel reports (.tck: every key; .trk: voxel_order).
  std::map<std::string, std::string> header;
  /// Empty on success; otherwise what went wrong (python's stderr).
  std::string error;
};

/// nibabel.streamlines.load(path) run by /usr/bin/python3.
LoadedStreamlines loadWithNibabel(const std::string& path);

/// A legacy ASCII VTK POLYDATA file with POINTS, LINES and float SCALARS.
LoadedStreamlines loadLegacyVtk(const std::string& path);

}  // namespace stvd::testing
