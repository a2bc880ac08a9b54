// Lanthier's method over a polygon surface: the Steiner-point layout over
// its faces (every face is one cell, M points on each edge are shared by the
// edge's faces) and the propagation over them.
#include "stvd/surface/surface_lanthier.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "stvd/propagation/detail/front_queue.hpp"
#include "surface/surface_steiner_cells.hpp"

namespace stvd::detail {

SurfaceSteinerCells::SurfaceSteinerCells(const SurfaceDomain& surface, int steinerPoints)
    : SurfaceSteinerCells(surface, steinerPoints, nullptr) {}

SurfaceSteinerCells::SurfaceSteinerCells(const SurfaceDomain& surface, int steinerPoints, SetupProgress& setup)
    : SurfaceSteinerCells(surface, steinerPoints, &setup) {}

std::uint64_t SurfaceSteinerCells::setupSteps(const SurfaceDomain& surface) {
  return 4 * std::uint64_t(surface.faces().faceCount()) + 3 * std::uint64_t(surface.vertexCount());
}

SurfaceSteinerCells::SurfaceSteinerCells(const SurfaceDomain& surface, int steinerPoints, SetupProgress* setup)
    : surface_(surface), m_(steinerPoints) {
  const PolygonList& faces = surface.faces();
  const std::size_t faceCount = faces.faceCount();
  const std::size_t cornerCount = faces.faceVertex.size();
  const std::size_t vertexCount = surface.vertexCount();
  auto nextCorner = [&](std::uint32_t f, std::uint32_t c) {
    return c + 1 < faces.faceStart[f + 1] ? c + 1 : faces.faceStart[f];
  };
  auto step = [&] {
    if (setup) setup->step();
  };

  // Undirected edges in (smaller, larger) vertex order, sorted: the
  // numbering of the edge points does not depend on the faces'
  // orientation. A counting sort by the smaller vertex, then each vertex's
  // few larger neighbours sorted: linear, and every loop reports.
  std::vector<std::uint32_t> sideStart(vertexCount + 1, 0);
  for (std::uint32_t f = 0; f < faceCount; ++f, step())
    for (std::uint32_t c = faces.faceStart[f]; c < faces.faceStart[f + 1]; ++c) {
      const VertexId a = faces.faceVertex[c], b = faces.faceVertex[nextCorner(f, c)];
      ++sideStart[std::min(a, b) + 1];
    }
  for (std::size_t v = 0; v < vertexCount; ++v, step()) sideStart[v + 1] += sideStart[v];
  std::vector<VertexId> larger(cornerCount);
  {
    std::vector<std::uint32_t> fill(sideStart.begin(), sideStart.end() - 1);
    for (std::uint32_t f = 0; f < faceCount; ++f, step())
      for (std::uint32_t c = faces.faceStart[f]; c < faces.faceStart[f + 1]; ++c) {
        const VertexId a = faces.faceVertex[c], b = faces.faceVertex[nextCorner(f, c)];
        larger[fill[std::min(a, b)]++] = std::max(a, b);
      }
  }
  // edgeStart[v]: the first edge whose smaller vertex is v.
  std::vector<std::uint32_t> edgeStart(vertexCount + 1, 0);
  edges_.reserve(cornerCount);
  for (std::size_t v = 0; v < vertexCount; ++v, step()) {
    edgeStart[v] = static_cast<std::uint32_t>(edges_.size());
    const auto begin = larger.begin() + sideStart[v], end = larger.begin() + sideStart[v + 1];
    std::sort(begin, end);
    for (auto b = begin; b != end; ++b)
      if (b == begin || *b != *(b - 1)) edges_.push_back({static_cast<VertexId>(v), *b});
  }
  edgeStart[vertexCount] = static_cast<std::uint32_t>(edges_.size());

  pointCount_ = surface.vertexCount() + std::uint64_t(m_) * edges_.size();
  if (pointCount_ >= FrontQueue::kFinal)
    throw std::invalid_argument("Steiner graph of " + std::to_string(pointCount_) +
                                " points is too large for 32-bit indices; use fewer Steiner points");

  sideEdge_.resize(cornerCount);
  edgeFace_.assign(edges_.size(), {kNoFace, kNoFace});
  vertexFaceStart_.assign(surface.vertexCount() + 1, 0);
  for (std::uint32_t f = 0; f < faceCount; ++f, step()) {
    maxCorners_ = std::max(maxCorners_, static_cast<int>(faces.faceStart[f + 1] - faces.faceStart[f]));
    for (std::uint32_t c = faces.faceStart[f]; c < faces.faceStart[f + 1]; ++c) {
      const VertexId a = faces.faceVertex[c], b = faces.faceVertex[nextCorner(f, c)];
      const std::array<VertexId, 2> key{std::min(a, b), std::max(a, b)};
      const auto first = edges_.begin() + edgeStart[key[0]], last = edges_.begin() + edgeStart[key[0] + 1];
      const auto e = static_cast<std::uint32_t>(std::lower_bound(first, last, key) - edges_.begin());
      sideEdge_[c] = e;
      // A manifold edge has at most two faces (SurfaceDomain checked that).
      edgeFace_[e][edgeFace_[e][0] == kNoFace ? 0 : 1] = f;
      ++vertexFaceStart_[a + 1];
    }
  }
  for (std::size_t v = 0; v < vertexCount; ++v, step()) vertexFaceStart_[v + 1] += vertexFaceStart_[v];
  vertexFace_.resize(cornerCount);
  {
    std::vector<std::uint32_t> fill(vertexFaceStart_.begin(), vertexFaceStart_.end() - 1);
    for (std::uint32_t f = 0; f < faceCount; ++f, step())
      for (std::uint32_t c = faces.faceStart[f]; c < faces.faceStart[f + 1]; ++c)
        vertexFace_[fill[faces.faceVertex[c]]++] = f;
  }
  const std::size_t points = std::size_t(maxCorners_) * (1 + std::size_t(m_));
  id_.resize(points);
  position_.resize(points);
}

Vec3d SurfaceSteinerCells::position(SteinerPointId p) const {
  const std::vector<Vec3d>& x = surface_.points();
  if (p < surface_.vertexCount()) return x[p];
  const std::uint32_t e = (p - surface_.vertexCount()) / m_, m = (p - surface_.vertexCount()) % m_ + 1;
  const std::array<VertexId, 2>& edge = edges_[e];
  return x[edge[0]] + (m / double(m_ + 1)) * (x[edge[1]] - x[edge[0]]);
}

int SurfaceSteinerCells::gather(std::uint32_t f) {
  const std::vector<Vec3d>& x = surface_.points();
  const PolygonList& faces = surface_.faces();
  const std::uint32_t begin = faces.faceStart[f], end = faces.faceStart[f + 1];
  const Vec3d origin = x[faces.faceVertex[begin]];
  const double step = 1.0 / (m_ + 1);
  int n = 0;
  for (std::uint32_t c = begin; c < end; ++c) {
    const VertexId v = faces.faceVertex[c];
    id_[n] = v;
    position_[n++] = toFloat(x[v] - origin);
  }
  for (std::uint32_t c = begin; c < end; ++c) {
    const std::uint32_t e = sideEdge_[c];
    const std::array<VertexId, 2>& edge = edges_[e];
    const Vec3d a = x[edge[0]] - origin, d = x[edge[1]] - x[edge[0]];
    const SteinerPointId first = static_cast<SteinerPointId>(surface_.vertexCount() + std::uint64_t(e) * m_);
    for (int m = 1; m <= m_; ++m) {
      id_[n] = first + (m - 1);
      position_[n++] = toFloat(a + (m * step) * d);
    }
  }
  return n;
}

}  // namespace stvd::detail

namespace stvd {

LanthierResult lanthierPropagate(const SurfaceDomain& surface, const RiemannianMetric& metric,
                                          const std::vector<VertexId>& sources, const LanthierOptions& options) {
  detail::validate(surface, surface.vertexCount(), metric, sources, options);
  return detail::setUpAndRunLanthier<detail::SurfaceSteinerCells>(
      metric, surface.vertexCount(), surface.vertexCount(), sources, options,
      detail::SurfaceSteinerCells::setupSteps(surface),
      // every edge is the side of a face
      surface.vertexCount() + std::uint64_t(options.steinerPoints) * surface.faces().faceVertex.size(),
      surface, options.steinerPoints);
}

Vec3d steinerPointPosition(const SurfaceDomain& surface, int steinerPoints, SteinerPointId p) {
  if (steinerPoints < 1 || steinerPoints > kMaxSteinerPoints)
    throw std::invalid_argument("number of Steiner points per edge M = " + std::to_string(steinerPoints) +
                                " is outside 1.." + std::to_string(kMaxSteinerPoints));
  const detail::SurfaceSteinerCells cells(surface, steinerPoints);
  if (p >= cells.pointCount()) throw std::invalid_argument("Steiner point " + std::to_string(p) + " out of range");
  return cells.position(p);
}

}  // namespace stvd
