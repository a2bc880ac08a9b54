#include "stvd/voxel_grid/label_regions.hpp"

#include <cmath>
#include <map>
#include <stdexcept>

#include "stvd/errors.hpp"

namespace stvd {

std::vector<LabelRegion> labelRegions(const std::vector<std::int64_t>& labels,
                                      const std::vector<std::uint8_t>& inDomain) {
  if (labels.size() != inDomain.size())
    throw std::invalid_argument("the labels have " + std::to_string(labels.size()) + " voxels, the domain " +
                                std::to_string(inDomain.size()));
  std::map<std::int64_t, LabelRegion> byLabel;
  for (std::size_t v = 0; v < labels.size(); ++v) {
    if (labels[v] == 0) continue;
    LabelRegion& r = byLabel[labels[v]];
    r.label = labels[v];
    if (inDomain[v]) r.voxels.push_back(static_cast<VertexId>(v));
  }
  std::vector<LabelRegion> regions;
  regions.reserve(byLabel.size());
  for (auto& [label, region] : byLabel) regions.push_back(std::move(region));
  return regions;
}

std::vector<LabelRegion> regionsInDomain(std::vector<LabelRegion> regions, const std::string& labelsName,
                                         const std::string& inputName, std::size_t& leftOut) {
  std::vector<LabelRegion> kept;
  for (LabelRegion& region : regions) {
    if (region.voxels.empty())
      ++leftOut;
    else
      kept.push_back(std::move(region));
  }
  if (kept.size() < 2)
    throw NothingToCompute(labelsName + ": fewer than two regions have voxels inside the domain of " + inputName);
  return kept;
}

VertexId nearestReached(const std::vector<double>& distance, const std::vector<VertexId>& vertices) {
  VertexId nearest = kNoVertex;
  for (VertexId v : vertices)
    if (std::isfinite(distance[v]) && (nearest == kNoVertex || distance[v] < distance[nearest])) nearest = v;
  return nearest;
}

}  // namespace stvd
