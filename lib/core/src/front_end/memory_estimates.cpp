#include "stvd/front_end/memory_estimates.hpp"

#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"

namespace stvd {

std::uint64_t propagationMemoryEstimate(std::uint64_t vertexCount, std::uint64_t domainVertexCount) {
  constexpr std::uint64_t kRecord = 16, kResult = sizeof(double) + sizeof(VertexId), kQueuePerVertex = 64;
  return (kRecord + kResult) * vertexCount + kQueuePerVertex * domainVertexCount + (std::uint64_t{1} << 20);
}

std::uint64_t lanthierMemoryEstimate(std::uint64_t graphPoints, std::uint64_t vertexCount) {
  constexpr std::uint64_t kPerPoint = 24, kResult = sizeof(double) + sizeof(VertexId);
  return kPerPoint * graphPoints + kResult * vertexCount + (std::uint64_t{1} << 20);
}

std::uint64_t gridRunMemoryEstimate(const PropagationChoice& choice, std::uint64_t voxels,
                                    std::uint64_t domainVoxels) {
  if (!choice.lanthier) return propagationMemoryEstimate(voxels, domainVoxels);
  return lanthierMemoryEstimate(lanthierGridPointCount(domainVoxels, choice.steinerPoints), voxels) +
         2 * sizeof(VertexId) * voxels;  // the grid cells' numbering of domain voxels
}

std::uint64_t surfaceRunMemoryEstimate(const PropagationChoice& choice, std::uint64_t vertices,
                                       std::uint64_t corners) {
  const std::uint64_t m = static_cast<std::uint64_t>(choice.steinerPoints);
  return 64 * vertices + (choice.lanthier ? lanthierMemoryEstimate(vertices + m * corners, vertices)
                                          : propagationMemoryEstimate(vertices, vertices));
}

std::uint64_t tetMeshRunMemoryEstimate(const PropagationChoice& choice, std::uint64_t vertices,
                                       std::uint64_t tetrahedra) {
  const std::uint64_t v = vertices, t = tetrahedra, m = static_cast<std::uint64_t>(choice.steinerPoints);
  constexpr std::uint64_t kMeshBytesPerVertex = 24 + 64, kDomainBytesPerTet = 16 + 160, kCellBytesPerTet = 160;
  return kMeshBytesPerVertex * v + kDomainBytesPerTet * t +
         (choice.lanthier ? kCellBytesPerTet * t + lanthierMemoryEstimate(v + 6 * m * t + 2 * m * (m - 1) * t, v)
                          : propagationMemoryEstimate(v, v));
}

}  // namespace stvd
