#include "stvd/cell_mesh/tetrahedral_cells.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace stvd {
namespace {

/// CSR incidence from (item, tet) pairs: first[item]..first[item + 1] index `tets`.
void buildIncidence(std::size_t itemCount, std::vector<std::pair<std::uint32_t, std::uint32_t>>& pairs,
                    std::vector<std::uint64_t>& first, std::vector<std::uint32_t>& tets) {
  std::sort(pairs.begin(), pairs.end());
  first.assign(itemCount + 1, 0);
  for (const auto& p : pairs) ++first[p.first + 1];
  for (std::size_t i = 0; i < itemCount; ++i) first[i + 1] += first[i];
  tets.resize(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) tets[i] = pairs[i].second;
}

}  // namespace

TetrahedralCells::TetrahedralCells(std::vector<Vec3d> points, std::vector<Tetrahedron> tets)
    : points_(std::move(points)), tets_(std::move(tets)) {
  if (tets_.empty()) throw std::invalid_argument("tetrahedral mesh has no tetrahedron");
  if (points_.size() >= kNone - 1)
    throw std::invalid_argument("tetrahedral mesh has too many points for 32-bit indices");
  const VertexId n = vertexCount();
  for (std::size_t t = 0; t < tets_.size(); ++t) {
    const Tetrahedron& c = tets_[t];
    for (int a = 0; a < 4; ++a) {
      if (c[a] >= n)
        throw std::invalid_argument("tetrahedron " + std::to_string(t) + " has vertex index " +
                                    std::to_string(c[a]) + " out of range (" + std::to_string(n) +
                                    " points)");
      for (int b = 0; b < a; ++b)
        if (c[a] == c[b])
          throw std::invalid_argument("tetrahedron " + std::to_string(t) + " repeats vertex " +
                                      std::to_string(c[a]));
    }
  }

  // Edges and faces: every tetrahedron's, sorted and deduplicated; each
  // tetrahedron then finds its own by binary search.
  constexpr int kEdgePairs[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (const Tetrahedron& c : tets_) {
    for (const auto& p : kEdgePairs) edges_.push_back({std::min(c[p[0]], c[p[1]]), std::max(c[p[0]], c[p[1]])});
    for (int f = 0; f < 4; ++f) {
      Face face;
      int m = 0;
      for (int a = 0; a < 4; ++a)
        if (a != f) face[m++] = c[a];
      std::sort(face.begin(), face.end());
      faces_.push_back(face);
    }
  }
  std::sort(edges_.begin(), edges_.end());
  edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
  std::sort(faces_.begin(), faces_.end());
  faces_.erase(std::unique(faces_.begin(), faces_.end()), faces_.end());

  tetEdges_.resize(tets_.size());
  tetFaces_.resize(tets_.size());
  faceTets_.assign(2 * faces_.size(), kNone);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> vertexPairs, edgePairs;
  vertexPairs.reserve(4 * tets_.size());
  edgePairs.reserve(6 * tets_.size());
  for (std::size_t t = 0; t < tets_.size(); ++t) {
    const Tetrahedron& c = tets_[t];
    const auto tet = static_cast<std::uint32_t>(t);
    for (int a = 0; a < 4; ++a) vertexPairs.emplace_back(c[a], tet);
    for (int e = 0; e < 6; ++e) {
      const Edge edge{std::min(c[kEdgePairs[e][0]], c[kEdgePairs[e][1]]),
                      std::max(c[kEdgePairs[e][0]], c[kEdgePairs[e][1]])};
      const auto id = static_cast<std::uint32_t>(
          std::lower_bound(edges_.begin(), edges_.end(), edge) - edges_.begin());
      tetEdges_[t][e] = id;
      edgePairs.emplace_back(id, tet);
    }
    for (int f = 0; f < 4; ++f) {
      Face face;
      int m = 0;
      for (int a = 0; a < 4; ++a)
        if (a != f) face[m++] = c[a];
      std::sort(face.begin(), face.end());
      const auto id = static_cast<std::uint32_t>(
          std::lower_bound(faces_.begin(), faces_.end(), face) - faces_.begin());
      tetFaces_[t][f] = id;
      std::uint32_t* slot = &faceTets_[2 * id];
      if (slot[0] == kNone) {
        slot[0] = tet;
      } else if (slot[1] == kNone) {
        slot[1] = tet;
      } else {
        throw std::invalid_argument("face (" + std::to_string(face[0]) + ", " + std::to_string(face[1]) +
                                    ", " + std::to_string(face[2]) +
                                    ") belongs to more than two tetrahedra");
      }
    }
  }
  buildIncidence(points_.size(), vertexPairs, vertexFirst_, vertexTets_);
  buildIncidence(edges_.size(), edgePairs, edgeFirst_, edgeTets_);
}

}  // namespace stvd
