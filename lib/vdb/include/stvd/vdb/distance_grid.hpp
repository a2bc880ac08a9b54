// Distance maps as sparse OpenVDB grids (.vdb), for tools that render or
// process volumes through OpenVDB (Houdini, Blender, ...). No OpenVDB
// header here: it is only included by the .cpp file, which is costly to
// compile.
#pragma once

#include <string>
#include <vector>

#include "stvd/system/files/output_transaction.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::vdb {

struct DistanceGridOptions {
  /// The grid's name in the file.
  std::string gridName = "distance";
  /// The value of inactive voxels (those not reached); must be finite.
  float background = -1.f;
};

/// Writes `distance` (one value per voxel of `geometry`, linear order
/// i + nx*(j + ny*k); +infinity or NaN = not reached) as an OpenVDB
/// FloatGrid: reached voxels are active and hold their distance, the others
/// are inactive. The grid's index-to-world transform maps voxel (i, j, k) to
/// its centre in RAS millimetres (the NIfTI/scanner convention; `geometry`
/// is in LPS as the imaging adapter reads it). The grid carries the
/// metadata "units" = "mm" and "world_frame" = "RAS". Written atomically
/// (stvd/system/files/output_transaction.hpp) and read back before it is moved into
/// place, since OpenVDB does not report a failed write. The file's UUID is
/// derived from its content, so that the same grid always gives the same
/// bytes. Throws std::runtime_error (files::OutputError when writing fails)
/// with a one-line message "<path>: <problem>".
void writeDistanceGrid(const std::string& path, const GridGeometry& geometry, const std::vector<double>& distance,
                       const DistanceGridOptions& options = {});

/// The same as one output of `outputs`, moved into place at its commit.
/// Throws files::OutputError (std::runtime_error for values that do not fit
/// the geometry).
void writeDistanceGrid(files::OutputTransaction& outputs, const std::string& path, const GridGeometry& geometry,
                       const std::vector<double>& distance, const DistanceGridOptions& options = {});

}  // namespace stvd::vdb
