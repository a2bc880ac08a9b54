#include "stvd/voxel_grid/grid_geometry.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace stvd {

Vec3d GridGeometry::physicalPointToIndex(Vec3d p) const {
  // direction is orthonormal (validate()), so its inverse is its transpose.
  const Vec3d d = p - Vec3d{origin[0], origin[1], origin[2]};
  const double u = direction[0] * d.x + direction[3] * d.y + direction[6] * d.z;
  const double v = direction[1] * d.x + direction[4] * d.y + direction[7] * d.z;
  const double w = direction[2] * d.x + direction[5] * d.y + direction[8] * d.z;
  return {u / spacing[0], v / spacing[1], w / spacing[2]};
}

void GridGeometry::validate() const {
  for (int a = 0; a < 3; ++a) {
    if (size[a] == 0) throw std::invalid_argument("grid size along axis " + std::to_string(a) + " is 0");
    if (!(std::isfinite(spacing[a]) && spacing[a] > 0.0))
      throw std::invalid_argument("grid spacing along axis " + std::to_string(a) +
                                  " is not a positive number: " + std::to_string(spacing[a]));
    if (!std::isfinite(origin[a])) throw std::invalid_argument("grid origin is not finite");
  }
  const double count = static_cast<double>(size[0]) * size[1] * size[2];
  if (count >= static_cast<double>(std::numeric_limits<VertexId>::max() - 1))
    throw std::invalid_argument("grid has too many voxels for 32-bit vertex indices");
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b) {
      double d = 0.0;
      for (int r = 0; r < 3; ++r) d += direction[3 * r + a] * direction[3 * r + b];
      if (!(std::abs(d - (a == b ? 1.0 : 0.0)) <= 1e-4))
        throw std::invalid_argument("grid direction cosines are not orthonormal");
    }
}

}  // namespace stvd
