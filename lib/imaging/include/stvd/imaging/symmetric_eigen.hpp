// Eigen-decomposition of a symmetric 3x3 tensor, and the scalar measures
// built from it.
#pragma once

#include <array>

#include "stvd/types.hpp"

namespace stvd::imaging {

/// T = sum_i values[i] * vectors[i] vectors[i]^T, values in descending order,
/// vectors orthonormal. Double precision.
struct SymmetricEigen {
  std::array<double, 3> values{};
  std::array<Vec3d, 3> vectors{};
};

/// Decomposes t (Eigen's SelfAdjointEigenSolver, the iterative QR variant,
/// which keeps small eigenvalues of ill-conditioned tensors accurate).
SymmetricEigen eigenDecompose(const SymTensor3& t);

/// sum_i values[i] * vectors[i] vectors[i]^T.
SymTensor3 tensorFromEigen(const std::array<double, 3>& values, const std::array<Vec3d, 3>& vectors);

/// Fractional anisotropy sqrt(3/2) |lambda - mean| / |lambda| (Basser and
/// Pierpaoli 1996). Above 1 when an eigenvalue is negative; 0 for a zero
/// tensor.
double fractionalAnisotropy(const std::array<double, 3>& values);

}  // namespace stvd::imaging
