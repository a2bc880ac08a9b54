// Regions of a label image on a voxel grid: each distinct non-zero integer
// value is a region. Seeds, path targets and connectivity are given this way.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "stvd/types.hpp"

namespace stvd {

/// A region: its label value and its voxels inside the domain (linear
/// indices, increasing; possibly none).
struct LabelRegion {
  std::int64_t label = 0;
  std::vector<VertexId> voxels;
};

/// One region per distinct non-zero label of `labels` (one label per voxel,
/// as imaging::readLabelImage reads them: exact integers), in increasing
/// label order. Throws std::invalid_argument when `labels` and `inDomain`
/// differ in size.
std::vector<LabelRegion> labelRegions(const std::vector<std::int64_t>& labels,
                                      const std::vector<std::uint8_t>& inDomain);

/// The regions with at least one voxel in the domain, to be connected
/// pairwise; `leftOut` counts the others. Throws NothingToCompute naming
/// `labelsName` and `inputName` when fewer than two remain.
std::vector<LabelRegion> regionsInDomain(std::vector<LabelRegion> regions, const std::string& labelsName,
                                         const std::string& inputName, std::size_t& leftOut);

/// Of `vertices`, the one with the smallest finite distance (the first of
/// equal ones), or kNoVertex when none has a finite distance.
VertexId nearestReached(const std::vector<double>& distance, const std::vector<VertexId>& vertices);

}  // namespace stvd
