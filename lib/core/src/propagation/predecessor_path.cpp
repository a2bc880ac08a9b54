#include "stvd/propagation/predecessor_path.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace stvd {

std::vector<VertexId> predecessorPath(const PropagationResult& result, VertexId target) {
  if (target >= result.distance.size() || result.predecessor.size() != result.distance.size())
    throw std::invalid_argument("target vertex " + std::to_string(target) + " is out of range");
  if (!result.hasPredecessors) throw std::invalid_argument(detail::kNoPredecessorsMessage);
  std::vector<VertexId> path;
  if (!std::isfinite(result.distance[target])) return path;
  VertexId v = target;
  path.push_back(v);
  while (result.predecessor[v] != kNoVertex) {
    v = result.predecessor[v];
    path.push_back(v);
    if (path.size() > result.distance.size()) throw std::logic_error("the predecessor chain has a cycle");
  }
  if (result.distance[v] != 0.0) throw std::logic_error("the predecessor chain does not end at a source");
  std::reverse(path.begin(), path.end());
  return path;
}

}  // namespace stvd
