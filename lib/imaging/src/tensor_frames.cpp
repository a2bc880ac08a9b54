#include "stvd/imaging/tensor_frames.hpp"

#include <algorithm>
#include <cmath>

namespace stvd::imaging {

SymTensor3 changeTensorFrame(const SymTensor3& t, const Matrix3& m) {
  const double a[9] = {t.xx, t.xy, t.xz, t.xy, t.yy, t.yz, t.xz, t.yz, t.zz};
  double ma[9];  // M * A
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      ma[3 * r + c] = m[3 * r] * a[c] + m[3 * r + 1] * a[3 + c] + m[3 * r + 2] * a[6 + c];
  auto entry = [&](int r, int c) {  // (M A M^T)[r][c]
    return ma[3 * r] * m[3 * c] + ma[3 * r + 1] * m[3 * c + 1] + ma[3 * r + 2] * m[3 * c + 2];
  };
  return {static_cast<float>(entry(0, 0)), static_cast<float>(entry(0, 1)),
          static_cast<float>(entry(0, 2)), static_cast<float>(entry(1, 1)),
          static_cast<float>(entry(1, 2)), static_cast<float>(entry(2, 2))};
}

Matrix3 rasToLps() { return {-1, 0, 0, 0, -1, 0, 0, 0, 1}; }

Matrix3 voxelAxes(const GridGeometry& geometry) { return geometry.direction; }

Matrix3 multiply(const Matrix3& a, const Matrix3& b) {
  Matrix3 p{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      p[3 * r + c] = a[3 * r] * b[c] + a[3 * r + 1] * b[3 + c] + a[3 * r + 2] * b[6 + c];
  return p;
}

double obliquityDegrees(const GridGeometry& geometry) {
  // Each index axis is compared with the coordinate axis it is closest to;
  // the largest of the three angles is the obliquity.
  double worst = 0.0;
  for (int c = 0; c < 3; ++c) {
    double largest = 0.0;
    for (int r = 0; r < 3; ++r) largest = std::max(largest, std::abs(geometry.direction[3 * r + c]));
    worst = std::max(worst, std::acos(std::min(1.0, largest)));
  }
  return worst * 180.0 / M_PI;
}

}  // namespace stvd::imaging
