// Uses the system Eigen; no ITK header may enter this file (ITK bundles
// another Eigen under the same names).
#include "stvd/imaging/symmetric_eigen.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace stvd::imaging {

SymmetricEigen eigenDecompose(const SymTensor3& t) {
  Eigen::Matrix3d m;
  m << t.xx, t.xy, t.xz, t.xy, t.yy, t.yz, t.xz, t.yz, t.zz;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(m, Eigen::ComputeEigenvectors);
  // Eigen sorts ascending; stvd reports descending.
  SymmetricEigen e;
  for (int i = 0; i < 3; ++i) {
    const int src = 2 - i;
    e.values[i] = solver.eigenvalues()(src);
    const auto v = solver.eigenvectors().col(src);
    e.vectors[i] = {v(0), v(1), v(2)};
  }
  return e;
}

SymTensor3 tensorFromEigen(const std::array<double, 3>& values, const std::array<Vec3d, 3>& vectors) {
  double xx = 0, xy = 0, xz = 0, yy = 0, yz = 0, zz = 0;
  for (int i = 0; i < 3; ++i) {
    const Vec3d& v = vectors[i];
    const double l = values[i];
    xx += l * v.x * v.x;
    xy += l * v.x * v.y;
    xz += l * v.x * v.z;
    yy += l * v.y * v.y;
    yz += l * v.y * v.z;
    zz += l * v.z * v.z;
  }
  return {static_cast<float>(xx), static_cast<float>(xy), static_cast<float>(xz),
          static_cast<float>(yy), static_cast<float>(yz), static_cast<float>(zz)};
}

double fractionalAnisotropy(const std::array<double, 3>& l) {
  const double norm2 = l[0] * l[0] + l[1] * l[1] + l[2] * l[2];
  if (!(norm2 > 0.0)) return 0.0;
  const double mean = (l[0] + l[1] + l[2]) / 3.0;
  const double dev2 = (l[0] - mean) * (l[0] - mean) + (l[1] - mean) * (l[1] - mean) + (l[2] - mean) * (l[2] - mean);
  return std::sqrt(1.5 * dev2 / norm2);
}

}  // namespace stvd::imaging
