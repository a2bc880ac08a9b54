// Lanthier's method over a tetrahedral mesh: the Steiner-point layout over
// its tetrahedra (M points per edge and a lattice on every face) and the
// propagation over them.
#include "stvd/cell_mesh/cell_mesh_lanthier.hpp"

#include <stdexcept>
#include <string>

#include "cell_mesh/tetrahedral_steiner_cells.hpp"
#include "stvd/propagation/detail/front_queue.hpp"

namespace stvd {
namespace detail {

TetSteinerCells::TetSteinerCells(const TetrahedralCells& cells, int steinerPoints)
    : cells_(cells), m_(steinerPoints), facePoints_(std::uint32_t(steinerPoints) * (steinerPoints - 1) / 2) {
  firstFacePoint_ = cells.vertexCount() + std::uint64_t(m_) * cells.edges().size();
  pointCount_ = firstFacePoint_ + std::uint64_t(facePoints_) * cells.faces().size();
  if (pointCount_ >= FrontQueue::kFinal)
    throw std::invalid_argument("Steiner graph of " + std::to_string(pointCount_) +
                                " points is too large for 32-bit indices; use fewer Steiner points");
  const double step = 1.0 / (m_ + 1);
  for (int b = 1; b < m_; ++b)
    for (int c = 1; c <= m_ - b; ++c) faceLattice_.push_back({b * step, c * step});
  const std::size_t points = 4 + 6 * std::size_t(m_) + 4 * std::size_t(facePoints_);
  id_.resize(points);
  position_.resize(points);
}

Vec3d TetSteinerCells::position(SteinerPointId p) const {
  const std::vector<Vec3d>& x = cells_.points();
  if (p < cells_.vertexCount()) return x[p];
  const double step = 1.0 / (m_ + 1);
  if (p < firstFacePoint_) {
    const std::uint32_t e = (p - cells_.vertexCount()) / m_, m = (p - cells_.vertexCount()) % m_ + 1;
    const TetrahedralCells::Edge& edge = cells_.edges()[e];
    return x[edge[0]] + (m * step) * (x[edge[1]] - x[edge[0]]);
  }
  const std::uint64_t q = p - firstFacePoint_;
  const TetrahedralCells::Face& face = cells_.faces()[q / facePoints_];
  const auto& w = faceLattice_[q % facePoints_];
  return x[face[0]] + w[0] * (x[face[1]] - x[face[0]]) + w[1] * (x[face[2]] - x[face[0]]);
}

void TetSteinerCells::gather(std::uint32_t t) {
  const std::vector<Vec3d>& x = cells_.points();
  const TetrahedralCells::Tetrahedron& tet = cells_.tets()[t];
  const Vec3d origin = x[tet[0]];
  const double step = 1.0 / (m_ + 1);
  std::size_t n = 0;
  for (const VertexId v : tet) {
    id_[n] = v;
    position_[n++] = toFloat(x[v] - origin);
  }
  for (const std::uint32_t e : cells_.tetEdges(t)) {
    const TetrahedralCells::Edge& edge = cells_.edges()[e];
    const Vec3d a = x[edge[0]] - origin, d = x[edge[1]] - x[edge[0]];
    const SteinerPointId first = static_cast<SteinerPointId>(cells_.vertexCount() + std::uint64_t(e) * m_);
    for (int m = 1; m <= m_; ++m) {
      id_[n] = first + (m - 1);
      position_[n++] = toFloat(a + (m * step) * d);
    }
  }
  for (const std::uint32_t f : cells_.tetFaces(t)) {
    const TetrahedralCells::Face& face = cells_.faces()[f];
    const Vec3d a = x[face[0]] - origin, d1 = x[face[1]] - x[face[0]], d2 = x[face[2]] - x[face[0]];
    const SteinerPointId first = static_cast<SteinerPointId>(firstFacePoint_ + std::uint64_t(f) * facePoints_);
    for (std::uint32_t q = 0; q < facePoints_; ++q) {
      id_[n] = first + q;
      position_[n++] = toFloat(a + faceLattice_[q][0] * d1 + faceLattice_[q][1] * d2);
    }
  }
}

}  // namespace detail

template <class Norm>
LanthierResult lanthierPropagate(const TetrahedralCells& mesh, const MetricField<Norm>& metric,
                                          const std::vector<VertexId>& sources, const LanthierOptions& options) {
  detail::validate(mesh, mesh.vertexCount(), metric, sources, options);
  const std::uint64_t m = static_cast<std::uint64_t>(options.steinerPoints);
  const std::uint64_t points =
      mesh.vertexCount() + m * mesh.edges().size() + m * (m - 1) / 2 * mesh.faces().size();
  return detail::setUpAndRunLanthier<detail::TetSteinerCells>(metric, mesh.vertexCount(), mesh.vertexCount(),
                                                               sources, options, 0, points, mesh,
                                                               options.steinerPoints);
}

Vec3d steinerPointPosition(const TetrahedralCells& mesh, int steinerPoints, SteinerPointId p) {
  const detail::TetSteinerCells cells(mesh, steinerPoints);
  if (p >= cells.pointCount()) throw std::invalid_argument("Steiner point " + std::to_string(p) + " out of range");
  return cells.position(p);
}

template LanthierResult lanthierPropagate(const TetrahedralCells&, const RiemannianMetric&,
                                                   const std::vector<VertexId>&, const LanthierOptions&);
template LanthierResult lanthierPropagate(const TetrahedralCells&, const RandersMetric&,
                                                   const std::vector<VertexId>&, const LanthierOptions&);

}  // namespace stvd
