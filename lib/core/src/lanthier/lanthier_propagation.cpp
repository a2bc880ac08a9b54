#include "stvd/lanthier/lanthier_propagation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "lanthier/steiner_cells.hpp"
#include "stvd/propagation/detail/front_queue.hpp"

namespace stvd {
namespace detail {

// --------------------------------------------------------- tetrahedral cells

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

// ------------------------------------------------------------------ Dijkstra

/// Dijkstra over the implicit Steiner graph of `cells`.
template <class Cells, class Norm>
class SteinerDijkstra {
 public:
  SteinerDijkstra(Cells& cells, const MetricField<Norm>& metric, VertexId vertexCount,
                  VertexId domainVertexCount, const SteinerOptions& options)
      : cells_(cells),
        metric_(metric),
        options_(options),
        vertexCount_(vertexCount),
        domainVertexCount_(domainVertexCount),
        distance_(cells.pointCount(), kUnreachable),
        queue_(cells.pointCount()),
        length_(cells.maxCellPoints()),
        corner_(cells.maxCellCorners()) {}

  SteinerPropagationResult run(const std::vector<VertexId>& sources) {
    for (const VertexId s : sources) {
      const SteinerPointId p = cells_.pointOfVertex(s);
      distance_[p] = 0.0;
      queue_.pushOrDecrease(p, 0.0);
    }
    std::vector<std::uint8_t> isTarget;
    std::size_t remainingTargets = 0;
    if (!options_.targets.empty()) {
      isTarget.assign(vertexCount_, 0);
      for (const VertexId t : options_.targets) {
        remainingTargets += isTarget[t] == 0 ? 1 : 0;
        isTarget[t] = 1;
      }
    }

    SteinerPropagationResult result;
    constexpr std::uint64_t kProgressInterval = 1u << 16;
    // Progress counts original vertices: they are finalised interleaved with
    // the Steiner points in distance order, and unlike the points they all
    // lie in the domain.
    PropagationProgress progress;
    progress.domainVertices = domainVertexCount_;
    std::uint64_t finalizedPoints = 0;
    while (!queue_.empty()) {
      if (queue_.minKey() > options_.maxDistance) {
        result.termination = Termination::MaxDistanceReached;
        break;
      }
      const SteinerPointId u = queue_.popMin();
      ++finalizedPoints;
      const VertexId v = cells_.vertexOfPoint(u);
      if (v != kNoVertex) {
        ++result.finalizedVertices;
        if (!isTarget.empty() && isTarget[v] && --remainingTargets == 0) {
          result.termination = Termination::TargetsReached;
          break;
        }
      }
      if (options_.progress && finalizedPoints % kProgressInterval == 0) {
        peakBytes_ = std::max(peakBytes_, stateBytes());
        progress.finalizedVertices = result.finalizedVertices;
        progress.frontDistance = distance_[u];
        if (!options_.progress(progress)) {
          result.termination = Termination::Cancelled;
          break;
        }
      }
      relax(u);
    }
    peakBytes_ = std::max(peakBytes_, stateBytes());

    result.relaxedEdges = relaxed_;
    result.peakStateBytes = peakBytes_ + isTarget.capacity();
    result.graphPoints = cells_.pointCount();
    result.distance.assign(vertexCount_, kUnreachable);
    result.predecessor.assign(vertexCount_, kNoVertex);
    for (VertexId w = 0; w < vertexCount_; ++w) {
      const SteinerPointId p = cells_.pointOfVertex(w);  // kNoVertex: a voxel outside the domain
      if (p != kNoVertex && queue_.isFinal(p)) result.distance[w] = distance_[p];
    }
    if (options_.keepPointDistances) {
      // Only final points carry a distance.
      for (std::uint64_t p = 0; p < distance_.size(); ++p)
        if (!queue_.isFinal(static_cast<SteinerPointId>(p))) distance_[p] = kUnreachable;
      result.pointDistance = std::move(distance_);
    }
    return result;
  }

 private:
  std::uint64_t stateBytes() const {
    return distance_.capacity() * sizeof(double) + queue_.capacityBytes() + length_.capacity() * sizeof(float) +
           corner_.capacity() * sizeof(corner_[0]);
  }

  // Every boundary point q of every cell around u gets du + ||x(q) - x(u)||
  // under the cell's norm. Final points need no test: their distance is at
  // most du, and no length is negative.
  STVD_HOT_LOOP void relax(SteinerPointId u) {
    const double du = distance_[u];
    float* length = length_.data();
    cells_.forEachCellAround(u, [&](const SteinerCellView& cell) {
      // A polygon face may have any number of corners: the scratch is sized
      // for the largest cell once. A grid's cells are mostly cubes, whose
      // norm takes a loop of constant length.
      const typename Norm::VertexParams** corner = corner_.data();
      auto cellNorm = [&](int count) STVD_ALWAYS_INLINE_LAMBDA {
        for (int c = 0; c < count; ++c) corner[c] = &metric_[cell.corners[c]];
        return CellNormRule<Norm>::params(corner, count);
      };
      const typename Norm::EdgeParams g = cell.cornerCount == 8 ? cellNorm(8) : cellNorm(cell.cornerCount);
      const Vec3f* x = cell.position;
      const Vec3f self = cell.self;
      const int n = cell.pointCount;
      STVD_SIMD_LOOP
      for (int l = 0; l < n; ++l) length[l] = Norm::length(g, x[l].x - self.x, x[l].y - self.y, x[l].z - self.z);
      for (int l = 0; l < n; ++l) {
        const SteinerPointId q = cell.idBase + cell.idOffset[l];
        const double candidate = du + static_cast<double>(length[l]);
        if (candidate < distance_[q]) {
          distance_[q] = candidate;
          queue_.pushOrDecrease(q, candidate);
        }
      }
      relaxed_ += static_cast<std::uint64_t>(n);
    });
  }

  Cells& cells_;
  const MetricField<Norm>& metric_;
  const SteinerOptions& options_;
  VertexId vertexCount_, domainVertexCount_;
  std::vector<double> distance_;
  FrontQueue queue_;
  std::vector<float> length_;
  std::vector<const typename Norm::VertexParams*> corner_;
  std::uint64_t relaxed_ = 0;
  std::uint64_t peakBytes_ = 0;
};

template <class DomainLike, class Norm>
void validate(const DomainLike& domain, VertexId vertexCount, const MetricField<Norm>& metric,
              const std::vector<VertexId>& sources, const SteinerOptions& options) {
  if (metric.size() != vertexCount)
    throw std::invalid_argument("metric has " + std::to_string(metric.size()) + " vertices but the domain has " +
                                std::to_string(vertexCount));
  if (sources.empty()) throw std::invalid_argument("no source vertex given");
  for (const VertexId s : sources)
    if (!domain.contains(s))
      throw std::invalid_argument("source vertex " + std::to_string(s) + " lies outside the domain");
  for (const VertexId t : options.targets)
    if (!domain.contains(t))
      throw std::invalid_argument("target vertex " + std::to_string(t) + " lies outside the domain");
  if (options.steinerPoints < 1 || options.steinerPoints > kMaxSteinerPoints)
    throw std::invalid_argument("number of Steiner points per edge M = " + std::to_string(options.steinerPoints) +
                                " is outside 1.." + std::to_string(kMaxSteinerPoints));
  if (std::isnan(options.maxDistance)) throw std::invalid_argument("maximum distance is NaN");
}

}  // namespace detail

template <class Norm>
SteinerPropagationResult steinerPropagate(const VoxelGridDomain& domain, const MetricField<Norm>& metric,
                                          const std::vector<VertexId>& sources, const SteinerOptions& options) {
  detail::validate(domain, domain.vertexCount(), metric, sources, options);
  detail::GridSteinerCells cells(domain, options.steinerPoints);
  return detail::SteinerDijkstra<detail::GridSteinerCells, Norm>(cells, metric, domain.vertexCount(),
                                                                 domain.domainVertexCount(), options)
      .run(sources);
}

template <class Norm>
SteinerPropagationResult steinerPropagate(const TetrahedralCells& mesh, const MetricField<Norm>& metric,
                                          const std::vector<VertexId>& sources, const SteinerOptions& options) {
  detail::validate(mesh, mesh.vertexCount(), metric, sources, options);
  detail::TetSteinerCells cells(mesh, options.steinerPoints);
  return detail::SteinerDijkstra<detail::TetSteinerCells, Norm>(cells, metric, mesh.vertexCount(),
                                                                mesh.vertexCount(), options)
      .run(sources);
}

SteinerPropagationResult steinerPropagate(const SurfaceDomain& surface, const RiemannianMetric& metric,
                                          const std::vector<VertexId>& sources, const SteinerOptions& options) {
  detail::validate(surface, surface.vertexCount(), metric, sources, options);
  detail::SurfaceSteinerCells cells(surface, options.steinerPoints);
  return detail::SteinerDijkstra<detail::SurfaceSteinerCells, RiemannianNorm>(
             cells, metric, surface.vertexCount(), surface.vertexCount(), options)
      .run(sources);
}

Vec3d steinerPointPosition(const VoxelGridDomain& domain, int steinerPoints, SteinerPointId p) {
  const detail::GridSteinerCells cells(domain, steinerPoints, false);
  if (p >= cells.pointCount()) throw std::invalid_argument("Steiner point " + std::to_string(p) + " out of range");
  return cells.position(p);
}

Vec3d steinerPointPosition(const TetrahedralCells& mesh, int steinerPoints, SteinerPointId p) {
  const detail::TetSteinerCells cells(mesh, steinerPoints);
  if (p >= cells.pointCount()) throw std::invalid_argument("Steiner point " + std::to_string(p) + " out of range");
  return cells.position(p);
}

Vec3d steinerPointPosition(const SurfaceDomain& surface, int steinerPoints, SteinerPointId p) {
  if (steinerPoints < 1 || steinerPoints > kMaxSteinerPoints)
    throw std::invalid_argument("number of Steiner points per edge M = " + std::to_string(steinerPoints) +
                                " is outside 1.." + std::to_string(kMaxSteinerPoints));
  const detail::SurfaceSteinerCells cells(surface, steinerPoints);
  if (p >= cells.pointCount()) throw std::invalid_argument("Steiner point " + std::to_string(p) + " out of range");
  return cells.position(p);
}

template SteinerPropagationResult steinerPropagate(const VoxelGridDomain&, const RiemannianMetric&,
                                                   const std::vector<VertexId>&, const SteinerOptions&);
template SteinerPropagationResult steinerPropagate(const VoxelGridDomain&, const RandersMetric&,
                                                   const std::vector<VertexId>&, const SteinerOptions&);
template SteinerPropagationResult steinerPropagate(const TetrahedralCells&, const RiemannianMetric&,
                                                   const std::vector<VertexId>&, const SteinerOptions&);
template SteinerPropagationResult steinerPropagate(const TetrahedralCells&, const RandersMetric&,
                                                   const std::vector<VertexId>&, const SteinerOptions&);

std::uint64_t steinerGridPointCount(std::uint64_t domainVoxelCount, int steinerPoints) {
  const std::uint64_t m = static_cast<std::uint64_t>(steinerPoints);
  return (1 + 3 * m + 3 * m * m) * domainVoxelCount;
}

std::uint64_t steinerMemoryEstimate(std::uint64_t graphPoints, std::uint64_t vertexCount) {
  constexpr std::uint64_t kPerPoint = 24, kResult = sizeof(double) + sizeof(VertexId);
  return kPerPoint * graphPoints + kResult * vertexCount + (std::uint64_t{1} << 20);
}

}  // namespace stvd
