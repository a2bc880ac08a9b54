#include "fod_crossing.hpp"

#include <cmath>
#include <cstddef>
#include <vector>

#include "stvd/imaging/spherical_harmonics.hpp"
#include "test_support.hpp"

namespace stvd::testing {

Vec3d crossingAxis(int bundle, double angleDegrees) {
  if (bundle == 0) return {1, 0, 0};
  if (angleDegrees == 90.0) return {0, 1, 0};  // exactly: the file the tests always wrote
  const double a = angleDegrees * M_PI / 180.0;
  return {std::cos(a), std::sin(a), 0};
}

double distanceFromCrossingAxis(int bundle, double angleDegrees, double i, double j) {
  const Vec3d u = crossingAxis(bundle, angleDegrees);
  const double di = i - kCrossingCentre, dj = j - kCrossingCentre;
  return std::abs(di * u.y - dj * u.x);
}

void writeFodCrossing(const std::string& path, double angleDegrees) {
  constexpr int kN = kCrossingSize, kCoefficients = 45;
  HandGeometry g;
  g.size = {kN, kN, 3};
  g.spacing = {1.0, 1.0, 1.0};
  const std::size_t voxels = std::size_t(kN) * kN * 3;
  std::vector<float> values(voxels * kCoefficients, 0.f);  // volume-major: coefficient j of voxel v at j * voxels + v
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < kN; ++j)
      for (int i = 0; i < kN; ++i)
        for (int b = 0; b < 2; ++b) {
          if (distanceFromCrossingAxis(b, angleDegrees, i, j) > kCrossingHalfWidth + 1e-9) continue;
          const Vec3d axis = crossingAxis(b, angleDegrees);
          const std::vector<double> y = imaging::evaluateShBasis(imaging::ShBasis::Tournier07, 8, axis.x, axis.y, axis.z);
          const std::size_t v = std::size_t(i) + kN * (std::size_t(j) + kN * std::size_t(k));
          for (int l = 0; l <= 8; l += 2)
            for (int m = -l; m <= l; ++m) {
              const int c = l * (l + 1) / 2 + m;
              values[std::size_t(c) * voxels + v] += static_cast<float>(std::exp(-0.02 * l * (l + 1)) * y[c]);
            }
        }
  writeScalarNiftiByHand(path, g, values, kCoefficients);
}

}  // namespace stvd::testing
