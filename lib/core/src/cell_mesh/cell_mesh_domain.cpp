#include "stvd/cell_mesh/cell_mesh_domain.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace stvd {

namespace {
void checkIndex(VertexId v, std::size_t count, const char* what, std::size_t element) {
  if (v >= count)
    throw std::invalid_argument(std::string(what) + " " + std::to_string(element) +
                                " refers to vertex " + std::to_string(v) + " but the mesh has " +
                                std::to_string(count) + " vertices");
}
}  // namespace

CellMeshDomain::CellMeshDomain(std::vector<Vec3d> points,
                               std::vector<std::array<VertexId, 2>> edges)
    : points_(std::move(points)) {
  if (points_.size() >= kNoVertex) throw std::invalid_argument("mesh has too many vertices");
  for (std::size_t v = 0; v < points_.size(); ++v) {
    const Vec3d& p = points_[v];
    if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z)))
      throw std::invalid_argument("vertex " + std::to_string(v) + " has a non-finite position");
  }
  // Both directions of every edge, sorted and deduplicated: the CSR rows.
  std::vector<std::array<VertexId, 2>> directed;
  directed.reserve(2 * edges.size());
  for (std::size_t e = 0; e < edges.size(); ++e) {
    const auto [a, b] = edges[e];
    checkIndex(a, points_.size(), "edge", e);
    checkIndex(b, points_.size(), "edge", e);
    if (a == b) continue;
    directed.push_back({a, b});
    directed.push_back({b, a});
  }
  std::sort(directed.begin(), directed.end());
  directed.erase(std::unique(directed.begin(), directed.end()), directed.end());
  firstNeighbor_.assign(points_.size() + 1, 0);
  for (const auto& d : directed) ++firstNeighbor_[d[0] + 1];
  for (std::size_t v = 0; v < points_.size(); ++v) firstNeighbor_[v + 1] += firstNeighbor_[v];
  neighbors_.reserve(directed.size());
  for (const auto& d : directed) neighbors_.push_back(d[1]);
}

CellMeshDomain CellMeshDomain::fromEdges(std::vector<Vec3d> points,
                                         std::vector<std::array<VertexId, 2>> edges) {
  return CellMeshDomain(std::move(points), std::move(edges));
}

CellMeshDomain CellMeshDomain::fromTetrahedra(std::vector<Vec3d> points,
                                              const std::vector<Tetrahedron>& tets) {
  std::vector<std::array<VertexId, 2>> edges;
  edges.reserve(6 * tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t) {
    const Tetrahedron& c = tets[t];
    for (int a = 0; a < 4; ++a) {
      checkIndex(c[a], points.size(), "tetrahedron", t);
      for (int b = a + 1; b < 4; ++b) {
        if (c[a] == c[b])
          throw std::invalid_argument("tetrahedron " + std::to_string(t) +
                                      " repeats vertex " + std::to_string(c[a]));
        edges.push_back({c[a], c[b]});
      }
    }
  }
  CellMeshDomain mesh(std::move(points), std::move(edges));
  mesh.region_ = TetrahedralRegion(mesh.points_, tets);
  return mesh;
}

CellMeshDomain CellMeshDomain::fromPolyhedra(std::vector<Vec3d> points,
                                             const std::vector<PolyhedralCell>& cells) {
  std::vector<std::array<VertexId, 2>> edges;
  for (std::size_t c = 0; c < cells.size(); ++c) {
    for (const auto& face : cells[c]) {
      if (face.size() < 3)
        throw std::invalid_argument("cell " + std::to_string(c) + " has a face with fewer than 3 vertices");
      for (std::size_t i = 0; i < face.size(); ++i) {
        checkIndex(face[i], points.size(), "cell", c);
        edges.push_back({face[i], face[(i + 1) % face.size()]});
      }
    }
  }
  return CellMeshDomain(std::move(points), std::move(edges));
}

}  // namespace stvd
