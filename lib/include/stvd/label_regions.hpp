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
  long label = 0;
  std::vector<VertexId> voxels;
};

/// One region per distinct non-zero value of `labels` (one value per voxel;
/// NaN counts as zero), in increasing label order. Throws InputError
/// ("<labelsName>: label value 2.500 is not an integer") at the first value
/// that is not an integer, and std::invalid_argument when `labels` and
/// `inDomain` differ in size.
std::vector<LabelRegion> labelRegions(const std::string& labelsName, const std::vector<float>& labels,
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
