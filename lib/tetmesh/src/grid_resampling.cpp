// Barycentric resampling of vertex values onto a voxel grid.
#include "stvd/tetmesh/grid_resampling.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace stvd::tetmesh {

std::vector<double> resampleOntoGrid(const TetMesh& mesh, const std::vector<double>& vertexValues,
                                     const GridGeometry& grid, MeshFrame frame, double outsideValue) {
  if (vertexValues.size() != mesh.vertexCount())
    throw std::invalid_argument("resampleOntoGrid: one value per vertex is needed");
  const std::size_t nx = grid.size[0], ny = grid.size[1], nz = grid.size[2];
  std::vector<double> out(nx * ny * nz, outsideValue);
  std::vector<std::uint8_t> done(out.size(), 0);
  auto toGridPhysical = [&](Vec3d p) { return frame == MeshFrame::Ras ? Vec3d{-p.x, -p.y, p.z} : p; };
  // Slightly negative barycentric coordinates still count, so that a voxel
  // centre on a face shared by two tetrahedra is found in one of them.
  const double tolerance = -1e-9;
  for (const auto& t : mesh.tets) {
    Vec3d p[4];
    for (int c = 0; c < 4; ++c) p[c] = toGridPhysical(mesh.points[t[c]]);
    const double total = signedVolume(p[0], p[1], p[2], p[3]);
    if (total == 0.0) continue;
    double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};
    for (int c = 0; c < 4; ++c) {
      const Vec3d index = grid.physicalPointToIndex(p[c]);
      const double v[3] = {index.x, index.y, index.z};
      for (int a = 0; a < 3; ++a) {
        lo[a] = std::min(lo[a], v[a]);
        hi[a] = std::max(hi[a], v[a]);
      }
    }
    long first[3], last[3];
    bool empty = false;
    for (int a = 0; a < 3; ++a) {
      first[a] = std::max(0L, static_cast<long>(std::ceil(lo[a] - 1e-9)));
      last[a] = std::min(static_cast<long>(grid.size[a]) - 1, static_cast<long>(std::floor(hi[a] + 1e-9)));
      if (first[a] > last[a]) empty = true;
    }
    if (empty) continue;
    const double values[4] = {vertexValues[t[0]], vertexValues[t[1]], vertexValues[t[2]], vertexValues[t[3]]};
    const bool reachable = std::isfinite(values[0]) && std::isfinite(values[1]) && std::isfinite(values[2]) &&
                           std::isfinite(values[3]);
    for (long k = first[2]; k <= last[2]; ++k)
      for (long j = first[1]; j <= last[1]; ++j)
        for (long i = first[0]; i <= last[0]; ++i) {
          const std::size_t voxel = static_cast<std::size_t>(i) + nx * (static_cast<std::size_t>(j) + ny * static_cast<std::size_t>(k));
          if (done[voxel]) continue;
          const Vec3d x = grid.indexToPhysicalPoint(double(i), double(j), double(k));
          const double b0 = signedVolume(x, p[1], p[2], p[3]) / total;
          const double b1 = signedVolume(p[0], x, p[2], p[3]) / total;
          const double b2 = signedVolume(p[0], p[1], x, p[3]) / total;
          const double b3 = signedVolume(p[0], p[1], p[2], x) / total;
          if (b0 < tolerance || b1 < tolerance || b2 < tolerance || b3 < tolerance) continue;
          // A centre on a face shared with a reachable tetrahedron takes its value.
          if (!reachable) continue;
          done[voxel] = 1;
          out[voxel] = b0 * values[0] + b1 * values[1] + b2 * values[2] + b3 * values[3];
        }
  }
  return out;
}

}  // namespace stvd::tetmesh
