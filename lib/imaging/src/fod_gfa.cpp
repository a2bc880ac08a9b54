#include "stvd/imaging/fod_gfa.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace stvd::imaging {

std::vector<float> fodGeneralisedFa(const FodField& field) {
  const int count = field.coefficientCount();
  // Squared norms of the basis functions, numbered j = l(l+1)/2 + m.
  std::vector<double> norm(static_cast<std::size_t>(count), 1.0);
  if (field.basis == ShBasis::Tournier07Legacy)
    for (int l = 0; l <= field.lmax; l += 2)
      for (int m = -l; m <= l; ++m)
        if (m != 0) norm[static_cast<std::size_t>(l * (l + 1) / 2 + m)] = 0.5;
  const std::size_t voxels = field.geometry.voxelCount();
  std::vector<float> gfa(voxels, 0.0f);
  for (std::size_t v = 0; v < voxels; ++v) {
    const float* c = field.voxelCoefficients(v);
    double total = 0;
    for (int j = 0; j < count; ++j) total += norm[static_cast<std::size_t>(j)] * double(c[j]) * double(c[j]);
    if (total <= 0) continue;
    const double share = double(c[0]) * double(c[0]) / total;
    gfa[v] = static_cast<float>(std::sqrt(std::clamp(1.0 - share, 0.0, 1.0)));
  }
  return gfa;
}

}  // namespace stvd::imaging
