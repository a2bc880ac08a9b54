// Streamline files (paths as polylines) for tractography viewers and
// nibabel: MRtrix .tck, TrackVis .trk and legacy VTK .vtk polydata. Every
// format stores RAS millimetres (scanner space) in the end, whatever its own
// convention; the points handed in are LPS, the frame of stvd's geometry.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include "stvd/system/files/output_transaction.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

/// Polylines with optional per-point and per-line values, placed relative to
/// the grid of a reference image.
struct StreamlineSet {
  /// The reference image's grid (LPS): the .trk header's dimensions, voxel
  /// sizes and voxel-to-RAS matrix come from it.
  GridGeometry geometry;
  /// Points in LPS millimetres, one vector per line.
  std::vector<std::vector<Vec3d>> lines;
  /// Per-point values: names (at most 10, at most 19 characters for .trk)
  /// and values[name][line][point].
  std::vector<std::string> pointValueNames;
  std::vector<std::vector<std::vector<float>>> pointValues;
  /// Per-line values: names (same limits) and values[name][line].
  std::vector<std::string> lineValueNames;
  std::vector<std::vector<float>> lineValues;
};

enum class StreamlineFormat { Tck, Trk, Vtk };

/// The format named by the extension (.tck, .trk, .vtk, any letter case).
std::optional<StreamlineFormat> streamlineFormatOf(const std::string& path);

/// The 4x4 voxel-index-to-RAS matrix of a grid (row-major): the NIfTI
/// sform, diag(-1, -1, 1) times the LPS matrix [D diag(spacing) | origin].
std::array<double, 16> voxelToRas(const GridGeometry& geometry);

/// Three letters naming the RAS direction each index axis points to most
/// (e.g. "LAS"), as nibabel's aff2axcodes gives them for voxelToRas.
std::string rasAxisCodes(const GridGeometry& geometry);

/// Writes the set in the format of the extension, atomically (the file
/// appears complete or not at all). Throws ImageIoError naming the file for
/// an unknown extension, an inconsistent set (value counts, names too long
/// or too many) or a failed write.
///
/// - .tck: MRtrix tracks, Float32LE points in RAS mm, each line ended by a
///   NaN triple and the file by an Inf triple. Per-line values go into the
///   header as "name: v1 v2 ..." entries (MRtrix keeps per-streamline data
///   in separate .tsf files; the TSV summary of `stvd path` has them too);
///   per-point values are not stored.
/// - .trk: TrackVis version 2, 1000-byte header whose vox_to_ras is
///   voxelToRas() and voxel_order rasAxisCodes(); points in TrackVis "voxmm"
///   space, (index + 0.5) * voxel size; per-point values as scalars,
///   per-line values as properties.
/// - .vtk: legacy ASCII POLYDATA with points in RAS mm ("SPACE=RAS" in the
///   title line), lines as LINES, per-line values as CELL_DATA and per-point
///   values as POINT_DATA scalars.
void writeStreamlines(const std::string& path, const StreamlineSet& set);

/// The same as one output of `outputs`, moved into place at its commit.
/// Throws ImageIoError for an unknown extension or an inconsistent set,
/// files::OutputError when writing fails.
void writeStreamlines(files::OutputTransaction& outputs, const std::string& path, const StreamlineSet& set);

}  // namespace stvd::imaging
