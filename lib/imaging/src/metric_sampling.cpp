// Log-Euclidean trilinear interpolation of a voxel metric.
#include "stvd/imaging/metric_sampling.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "stvd/imaging/symmetric_eigen.hpp"

namespace stvd::imaging {
namespace {

SymTensor3 matrixFunction(const SymTensor3& t, double (*f)(double)) {
  const SymmetricEigen e = eigenDecompose(t);
  return tensorFromEigen({f(e.values[0]), f(e.values[1]), f(e.values[2])}, e.vectors);
}

double logPositive(double x) { return std::log(x); }
double expFunction(double x) { return std::exp(x); }

}  // namespace

SampledMetric sampleMetricLogEuclidean(const GridGeometry& geometry, const std::vector<SymTensor3>& voxelMetric,
                                       const std::vector<std::uint8_t>& voxelInDomain,
                                       const std::vector<Vec3d>& pointsLps) {
  const std::size_t nx = geometry.size[0], ny = geometry.size[1], nz = geometry.size[2];
  if (voxelMetric.size() != nx * ny * nz || voxelInDomain.size() != voxelMetric.size())
    throw std::invalid_argument("sampleMetricLogEuclidean: metric or domain size differs from the grid's");
  SampledMetric out;
  out.metric.assign(pointsLps.size(), SymTensor3{1.f, 0.f, 0.f, 1.f, 0.f, 1.f});
  out.inDomain.assign(pointsLps.size(), 0);

  // Logarithms are computed once per voxel, when a point first needs them.
  std::vector<SymTensor3> logs(voxelMetric.size());
  std::vector<std::uint8_t> haveLog(voxelMetric.size(), 0);
  auto logOf = [&](std::size_t voxel) -> const SymTensor3& {
    if (!haveLog[voxel]) {
      logs[voxel] = matrixFunction(voxelMetric[voxel], logPositive);
      haveLog[voxel] = 1;
    }
    return logs[voxel];
  };

  const std::size_t size[3] = {nx, ny, nz};
  for (std::size_t p = 0; p < pointsLps.size(); ++p) {
    const Vec3d index = geometry.physicalPointToIndex(pointsLps[p]);
    const double c[3] = {index.x, index.y, index.z};
    std::size_t lower[3];
    double fraction[3];
    bool inside = true;
    for (int a = 0; a < 3; ++a) {
      const double last = static_cast<double>(size[a] - 1);
      if (!(c[a] >= -0.5 && c[a] <= last + 0.5)) inside = false;
      const double clamped = std::clamp(c[a], 0.0, last);
      lower[a] = std::min(static_cast<std::size_t>(std::floor(clamped)), size[a] > 1 ? size[a] - 2 : 0);
      fraction[a] = size[a] > 1 ? clamped - static_cast<double>(lower[a]) : 0.0;
    }
    if (!inside) {
      out.outsideImage.push_back(p);
      continue;
    }
    double sum[6] = {0, 0, 0, 0, 0, 0};
    double weightSum = 0.0;
    for (int corner = 0; corner < 8; ++corner) {
      std::size_t at[3];
      double w = 1.0;
      for (int a = 0; a < 3; ++a) {
        const int up = (corner >> a) & 1;
        if (up && size[a] == 1) {
          w = 0.0;
          break;
        }
        at[a] = lower[a] + static_cast<std::size_t>(up);
        w *= up ? fraction[a] : 1.0 - fraction[a];
      }
      if (w <= 0.0) continue;
      const std::size_t voxel = at[0] + nx * (at[1] + ny * at[2]);
      if (!voxelInDomain[voxel]) continue;
      const SymTensor3& l = logOf(voxel);
      const double comps[6] = {l.xx, l.xy, l.xz, l.yy, l.yz, l.zz};
      for (int i = 0; i < 6; ++i) sum[i] += w * comps[i];
      weightSum += w;
    }
    if (weightSum <= 0.0) continue;
    const SymTensor3 meanLog{static_cast<float>(sum[0] / weightSum), static_cast<float>(sum[1] / weightSum),
                             static_cast<float>(sum[2] / weightSum), static_cast<float>(sum[3] / weightSum),
                             static_cast<float>(sum[4] / weightSum), static_cast<float>(sum[5] / weightSum)};
    out.metric[p] = matrixFunction(meanLog, expFunction);
    out.inDomain[p] = 1;
  }
  return out;
}

}  // namespace stvd::imaging
