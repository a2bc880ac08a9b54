#include "stvd/vdb/distance_grid.hpp"

#include <openvdb/openvdb.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <mutex>
#include <stdexcept>

#include "stvd/system/files/output_transaction.hpp"

namespace stvd::vdb {
namespace {

std::runtime_error failure(const std::string& path, const std::string& problem) {
  return std::runtime_error(path + ": " + problem);
}

openvdb::FloatGrid::Ptr distanceGrid(const std::string& path, const GridGeometry& geometry,
                                     const std::vector<double>& distance, const DistanceGridOptions& options) {
  if (distance.size() != geometry.voxelCount())
    throw failure(path, std::to_string(distance.size()) + " values for a grid of " +
                            std::to_string(geometry.voxelCount()) + " voxels");
  if (!std::isfinite(options.background)) throw failure(path, "the background value of a .vdb grid must be finite");
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
  return grid;
}

/// OpenVDB writes through a stream whose state it never checks: a full disk
/// leaves a truncated file and no error. The file is read back and every
/// active voxel compared.
void checkReadsBack(const std::string& file, const std::string& path, const openvdb::FloatGrid& written) {
  openvdb::FloatGrid::Ptr back;
  try {
    openvdb::io::File reader(file);
    reader.open(/*delayLoad=*/false);
    back = openvdb::gridPtrCast<openvdb::FloatGrid>(reader.readGrid(written.getName()));
    reader.close();
  } catch (const std::exception& e) {
    std::string reason = e.what();
    while (!reason.empty() && std::isspace(static_cast<unsigned char>(reason.back()))) reason.pop_back();
    throw failure(path, "the written file does not read back (disk full or file size limit?): " + reason);
  }
  bool same = back && back->activeVoxelCount() == written.activeVoxelCount() &&
              back->background() == written.background();
  if (same) {
    openvdb::FloatGrid::ConstAccessor values = back->getConstAccessor();
    for (auto voxel = written.cbeginValueOn(); same && voxel; ++voxel)
      same = values.isValueOn(voxel.getCoord()) && values.getValue(voxel.getCoord()) == *voxel;
  }
  if (!same) throw failure(path, "the written file reads back a different grid");
}

/// OpenVDB gives every file a random UUID (36 characters after the 21-byte
/// header start: magic, three version numbers, a flag), so equal grids make
/// different files. The UUID is replaced by one derived from the rest of
/// the file, which makes the output a function of its content.
void makeUuidFromContent(const std::string& file, const std::string& path) {
  constexpr std::size_t kUuidOffset = 21, kUuidLength = 36;
  std::fstream io(file, std::ios::in | std::ios::out | std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(io)), std::istreambuf_iterator<char>());
  if (bytes.size() < kUuidOffset + kUuidLength) throw failure(path, "the written file is too short for a .vdb file");
  for (std::size_t i = 0; i < kUuidLength; ++i) {
    const char c = bytes[kUuidOffset + i];
    const bool dash = i == 8 || i == 13 || i == 18 || i == 23;
    if (dash ? c != '-' : !std::isxdigit(static_cast<unsigned char>(c))) return;  // not the layout we know
  }
  // Two 64-bit FNV-1a hashes of everything but the UUID, with different
  // starting values, printed as a version-8 (custom) UUID.
  std::uint64_t h[2] = {1469598103934665603ull, 1099511628211ull * 31};
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    if (i >= kUuidOffset && i < kUuidOffset + kUuidLength) continue;
    for (std::uint64_t& x : h) x = (x ^ static_cast<unsigned char>(bytes[i])) * 1099511628211ull;
  }
  char uuid[kUuidLength + 1];
  std::snprintf(uuid, sizeof uuid, "%08x-%04x-8%03x-%04x-%012llx", static_cast<unsigned>(h[0] >> 32),
                static_cast<unsigned>((h[0] >> 16) & 0xffff), static_cast<unsigned>(h[0] & 0xfff),
                static_cast<unsigned>(0x8000 | ((h[1] >> 48) & 0x3fff)),
                static_cast<unsigned long long>(h[1] & 0xffffffffffffull));
  io.clear();
  io.seekp(static_cast<std::streamoff>(kUuidOffset));
  io.write(uuid, kUuidLength);
  if (!io.flush()) throw failure(path, "cannot write the file's UUID");
}

void writeGridTo(const std::string& file, const std::string& path, const openvdb::FloatGrid::Ptr& grid) {
  try {
    openvdb::io::File writer(file);
    writer.write({grid});
    writer.close();
  } catch (const std::exception& e) {
    throw failure(path, std::string("cannot write the OpenVDB file: ") + e.what());
  }
  checkReadsBack(file, path, *grid);
  makeUuidFromContent(file, path);
}

}  // namespace

void writeDistanceGrid(const std::string& path, const GridGeometry& geometry, const std::vector<double>& distance,
                       const DistanceGridOptions& options) {
  const openvdb::FloatGrid::Ptr grid = distanceGrid(path, geometry, distance, options);
  files::writeAtomically(path, [&](const std::string& staging) { writeGridTo(staging, path, grid); });
}

void writeDistanceGrid(files::OutputTransaction& outputs, const std::string& path, const GridGeometry& geometry,
                       const std::vector<double>& distance, const DistanceGridOptions& options) {
  const openvdb::FloatGrid::Ptr grid = distanceGrid(path, geometry, distance, options);
  outputs.write(path, [&](const std::string& staging) { writeGridTo(staging, path, grid); });
}

}  // namespace stvd::vdb
