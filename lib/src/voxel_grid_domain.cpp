#include "stvd/voxel_grid_domain.hpp"

#include <stdexcept>
#include <string>

namespace stvd {

VoxelGridDomain::VoxelGridDomain(const GridGeometry& geometry, Stencil stencil,
                                 std::vector<std::uint8_t> mask)
    : geometry_(geometry), stencil_(std::move(stencil)), mask_(std::move(mask)) {
  geometry_.validate();
  nx_ = static_cast<VertexId>(geometry_.size[0]);
  ny_ = static_cast<VertexId>(geometry_.size[1]);
  nz_ = static_cast<VertexId>(geometry_.size[2]);
  nxy_ = nx_ * ny_;
  vertexCount_ = static_cast<VertexId>(geometry_.voxelCount());
  rowDivisor_ = detail::FixedDivisor(nx_);
  sliceDivisor_ = detail::FixedDivisor(nxy_);
  if (!mask_.empty() && mask_.size() != vertexCount_)
    throw std::invalid_argument("mask has " + std::to_string(mask_.size()) +
                                " voxels but the grid has " + std::to_string(vertexCount_));
  domainVertexCount_ = vertexCount_;
  if (!mask_.empty()) {
    domainVertexCount_ = 0;
    for (std::uint8_t m : mask_) domainVertexCount_ += m != 0 ? 1 : 0;
  }
  for (const auto& o : stencil_.offsets()) {
    linearOffset_.push_back(o[0] + static_cast<std::int64_t>(nx_) * (o[1] + static_cast<std::int64_t>(ny_) * o[2]));
    edgeVector_.push_back(toFloat(geometry_.indexToPhysicalOffset(o[0], o[1], o[2])));
  }
}

}  // namespace stvd
