// Whether a file's tensors look like diffusion tensors read in the right
// layout. A wrong component order does not make a file unreadable: it mixes
// diagonal and off-diagonal components, and most tensors then get a
// negative eigenvalue (FA above 1 is one sign of it). Read so, a real brain
// has 86 to 100 % of its tensors not positive definite; read right, well
// under 1 % (fitting noise at the brain's edge and in CSF). The repairs
// would silently turn the former into a plausible-looking but wrong metric.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "stvd/imaging/tensor_layout.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/imaging/tensor_volume.hpp"

namespace stvd::imaging {

/// Tensors are implausible when more than this share of those with a value
/// (finite, non-zero, inside the masks) is not positive definite.
inline constexpr double kMaxNotPositiveDefiniteShare = 0.10;

/// Empty when the counts are plausible; otherwise what is wrong, e.g.
/// "132,798 of its 132,892 tensors (99.9 %) are not positive definite
/// (132,316 with FA above 1)".
std::string implausibleTensorsReason(const MetricVoxelCounts& counts);

/// How the tensors of a file look when its six numbers are read in `order`.
struct ComponentOrderTrial {
  TensorOrder order = TensorOrder::Lower;
  std::uint64_t tensors = 0;           ///< finite, non-zero, inside the mask
  std::uint64_t positiveDefinite = 0;  ///< of those, all eigenvalues > 0
  std::uint64_t faAboveOne = 0;        ///< of those, FA above 1
};

/// Reads the file's components once more in each of the three orders (the
/// components as stored, recovered from the LPS tensors through
/// info.componentsToLps) and counts the positive definite tensors. `mask`
/// is empty or one byte per voxel (0 = left out). Eigenvalue signs do not
/// depend on the frame, so the frame as read does not matter here.
std::vector<ComponentOrderTrial> tryComponentOrders(const TensorReadResult& read,
                                                    const std::vector<std::uint8_t>& mask);

}  // namespace stvd::imaging
