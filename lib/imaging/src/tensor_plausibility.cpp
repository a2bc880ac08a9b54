#include "stvd/imaging/tensor_plausibility.hpp"

#include <cmath>
#include <cstdio>

#include "stvd/imaging/symmetric_eigen.hpp"
#include "stvd/imaging/tensor_frames.hpp"

namespace stvd::imaging {
namespace {

std::string withThousands(std::uint64_t n) {
  std::string digits = std::to_string(n), out;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i != 0 && (digits.size() - i) % 3 == 0) out += ',';
    out += digits[i];
  }
  return out;
}

std::string percent(std::uint64_t part, std::uint64_t whole) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f %%", whole ? 100.0 * double(part) / double(whole) : 0.0);
  return text;
}

/// The inverse of a 3x3 matrix (row-major); the identity when singular.
Matrix3 inverse(const Matrix3& m) {
  const double c00 = m[4] * m[8] - m[5] * m[7], c01 = m[5] * m[6] - m[3] * m[8], c02 = m[3] * m[7] - m[4] * m[6];
  const double det = m[0] * c00 + m[1] * c01 + m[2] * c02;
  if (!(std::abs(det) > 0.0)) return {1, 0, 0, 0, 1, 0, 0, 0, 1};
  const double s = 1.0 / det;
  return {c00 * s, (m[2] * m[7] - m[1] * m[8]) * s, (m[1] * m[5] - m[2] * m[4]) * s,
          c01 * s, (m[0] * m[8] - m[2] * m[6]) * s, (m[2] * m[3] - m[0] * m[5]) * s,
          c02 * s, (m[1] * m[6] - m[0] * m[7]) * s, (m[0] * m[4] - m[1] * m[3]) * s};
}

}  // namespace

std::string implausibleTensorsReason(const MetricVoxelCounts& counts) {
  const std::uint64_t tensors = counts.withTensor();
  if (tensors == 0 ||
      !(double(counts.notPositiveDefinite) > kMaxNotPositiveDefiniteShare * double(tensors)))
    return {};
  return withThousands(counts.notPositiveDefinite) + " of its " + withThousands(tensors) + " tensors (" +
         percent(counts.notPositiveDefinite, tensors) + ") are not positive definite (" +
         withThousands(counts.faAboveOne) + " with FA above 1)";
}

std::vector<ComponentOrderTrial> tryComponentOrders(const TensorReadResult& read,
                                                    const std::vector<std::uint8_t>& mask) {
  const Matrix3 lpsToFile = inverse(read.info.componentsToLps);
  std::vector<ComponentOrderTrial> trials;
  for (TensorOrder order : {TensorOrder::Lower, TensorOrder::Fsl, TensorOrder::Mrtrix}) trials.push_back({order});
  float stored[6];
  const std::vector<SymTensor3>& tensors = read.volume.tensors;
  for (std::size_t v = 0; v < tensors.size(); ++v) {
    if (!mask.empty() && mask[v] == 0) continue;
    const SymTensor3& t = tensors[v];
    const float c[6] = {t.xx, t.xy, t.xz, t.yy, t.yz, t.zz};
    bool finite = true, zero = true;
    for (float x : c) {
      finite = finite && std::isfinite(x);
      zero = zero && x == 0.f;
    }
    if (!finite || zero) continue;
    componentsOfTensor(changeTensorFrame(t, lpsToFile), read.info.order, stored);
    for (ComponentOrderTrial& trial : trials) {
      const SymmetricEigen e = eigenDecompose(tensorFromComponents(stored, trial.order));
      ++trial.tensors;
      if (e.values[2] > 0.0) ++trial.positiveDefinite;
      if (fractionalAnisotropy(e.values) > 1.0) ++trial.faAboveOne;
    }
  }
  return trials;
}

}  // namespace stvd::imaging
