// What the tensor and the FOD bindings share for paths and connectivity
// (volume_bindings.cpp, fod_bindings.cpp): a path as the dict stvd.Paths
// takes, the paths written as `stvd path` writes them, and a connectivity
// table as the dict stvd.Connectivity takes.
#pragma once

#include <pybind11/pybind11.h>

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "stvd/imaging/seed_voxels.hpp"
#include "stvd/system/files/output_transaction.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"
#include "stvd/voxel_grid/label_regions.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/voxel_grid/region_connectivity.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd::python {

namespace py = pybind11;

/// One path of `target` as a dict (points in RAS millimetres, the figures
/// of `stvd path`'s table); `fa` null: no FA along it (NaN mean, None).
py::dict pathRecord(const VoxelGridDomain& domain, const imaging::PathTarget& target, const TracedPath& path,
                    const PathSamples* fa);

/// Stages the paths (RAS millimetres) on grid `g` in `outputs` as `stvd
/// path` writes them (stvd/imaging/streamline_io.hpp).
void writePathsOnGrid(const GridGeometry& g, files::OutputTransaction& outputs, const std::string& path,
                      const py::list& lines, const std::vector<double>& geodesic, const std::vector<double>& euclidean,
                      const std::optional<std::vector<double>>& meanFa, const py::object& fa);

/// The regions' labels and voxel counts and the n x n matrices (NaN on the
/// diagonal and where not reachable) as stvd.Connectivity takes them.
py::dict connectivityDict(const std::vector<LabelRegion>& regions, const RegionConnectivity& table,
                          std::size_t labelsLeftOut);

}  // namespace stvd::python
