#include "stvd/vdb/distance_grid.hpp"

#include <openvdb/openvdb.h>

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <mutex>
#include <stdexcept>

namespace stvd::vdb {

void writeDistanceGrid(const std::string& path, const GridGeometry& geometry, const std::vector<double>& distance,
                       const DistanceGridOptions& options) {
  auto fail = [&path](const std::string& problem) { return std::runtime_error(path + ": " + problem); };
  if (distance.size() != geometry.voxelCount())
    throw fail(std::to_string(distance.size()) + " values for a grid of " + std::to_string(geometry.voxelCount()) +
               " voxels");
  if (!std::isfinite(options.background)) throw fail("the background value of a .vdb grid must be finite");
  const std::filesystem::path target(path);
  const std::filesystem::path folder = target.parent_path().empty() ? "." : target.parent_path();
  if (!std::filesystem::is_directory(folder)) throw fail("the output folder '" + folder.string() + "' does not exist");
  static std::once_flag once;
  std::call_once(once, [] { openvdb::initialize(); });

  openvdb::FloatGrid::Ptr grid = openvdb::FloatGrid::create(options.background);
  {
    openvdb::FloatGrid::Accessor voxels = grid->getAccessor();
    const std::size_t nx = geometry.size[0], ny = geometry.size[1];
    for (std::size_t v = 0; v < distance.size(); ++v) {
      if (!std::isfinite(distance[v])) continue;
      const openvdb::Coord ijk(static_cast<int>(v % nx), static_cast<int>((v / nx) % ny),
                               static_cast<int>(v / (nx * ny)));
      voxels.setValueOn(ijk, static_cast<float>(distance[v]));
    }
  }
  // OpenVDB multiplies row vectors: world = (i, j, k, 1) * M, so the
  // linear part is the transpose of F * direction * diag(spacing), with
  // F = diag(-1, -1, 1) taking LPS to RAS, and the last row the origin.
  const double flip[3] = {-1.0, -1.0, 1.0};
  openvdb::math::Mat4d m = openvdb::math::Mat4d::identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m(c, r) = flip[r] * geometry.direction[3 * r + c] * geometry.spacing[c];
    m(3, r) = flip[r] * geometry.origin[r];
  }
  grid->setTransform(openvdb::math::Transform::createLinearTransform(m));
  grid->setName(options.gridName);
  grid->setGridClass(openvdb::GRID_UNKNOWN);
  grid->insertMeta("units", openvdb::StringMetadata("mm"));
  grid->insertMeta("world_frame", openvdb::StringMetadata("RAS"));

  // A temporary name in the same folder, renamed once complete.
  const std::filesystem::path staging =
      folder / ("." + target.filename().string() + ".stvd-" + std::to_string(::getpid()) + ".tmp");
  try {
    openvdb::io::File file(staging.string());
    file.write({grid});
    file.close();
    std::filesystem::rename(staging, target);
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove(staging, ec);
    throw fail(std::string("cannot write the OpenVDB file: ") + e.what());
  }
}

}  // namespace stvd::vdb
