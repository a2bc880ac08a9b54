#include "stvd/imaging/fod_run_description.hpp"

#include "stvd/imaging/fod_segment_norm.hpp"

namespace stvd::imaging {

std::string fodNormDescription(bool segments) {
  if (!segments) return "convexified F* along the 26 neighbour directions";
  return "convexified F* along the lattice directions of order " + std::to_string(kFodLatticeOrder) + " (" +
         std::to_string(FodSegmentNorm::kCount) + " per voxel), interpolated";
}

}  // namespace stvd::imaging
