// Definition of stvd::propagate. Include this header only to instantiate the
// propagation for a domain or a norm of your own; the built-in combinations
// are compiled in the library.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "stvd/chain_unfolding.hpp"
#include "stvd/detail/front_queue.hpp"
#include "stvd/large_array.hpp"
#include "stvd/propagation.hpp"

namespace stvd {
namespace detail {

/// The short-term memory of one finalised vertex v: its predecessor chain
/// c_0 = v, c_1 = pred(v), ..., c_m (m < k, shorter near a source), laid out
/// for the per-neighbour update. It is the same for every neighbour w of v,
/// so it is gathered once per finalised vertex.
///
/// Candidate i = 2..m+1 of the update of w lives in SIMD lane L = i - 2: its
/// sum vector is E_i = e_1 + ... + e_i = x(w) - x(c_{i-1}) and its base
/// distance is dist(c_{i-1}). Chain edge j >= 2 runs from c_{j-1} to c_{j-2}
/// (the direction of propagation) and is measured with the norm of its end
/// points; edge 1 (v -> w) is supplied per neighbour.
template <class Norm>
struct ChainMemory {
  static constexpr int kMaxLanes = 16;
  using EdgeParams = typename Norm::EdgeParams;
  int edgeCount;  // m + 1: edges 1..m+1
  alignas(64) float backX[kMaxLanes], backY[kMaxLanes], backZ[kMaxLanes];  // x(c_{L+1}) - x(v)
  alignas(64) double baseDistance[kMaxLanes];  // dist(c_{L+1}); +inf in padding lanes
  Vec3f edge[kMaxMemoryDepth + 1];             // e_j, j = 2..m+1
  EdgeParams edgeNorm[kMaxMemoryDepth + 1];
};

/// l_g(E_i) for all candidates of one neighbour at once, one lane per i.
///
/// ChainMeasure::ProjectionWeighted (section 6 of the paper):
///   l_g(E) = max(0, sum_j (e_j . Ebar) ||Ebar||_{g_j}),  Ebar = E / |E|:
/// E is split among its edges by their signed projections, and each portion
/// is measured with that edge's own norm.
/// ChainMeasure::LargestEdgeNorm:
///   l_g(E) = |E| max_j ||Ebar||_{g_j}:
/// the whole of E is measured with the most expensive of the chain's norms
/// in its direction.
/// A constant norm gives exactly |E| ||Ebar|| = ||E|| with either rule.
template <int Lanes, ChainMeasure Measure, class Norm>
STVD_ALWAYS_INLINE void chainSumLengths(const ChainMemory<Norm>& chain, Vec3f e1,
                                        const typename Norm::EdgeParams& g1, float* out) {
  alignas(64) float ux[Lanes], uy[Lanes], uz[Lanes], acc[Lanes], length[Lanes];
  STVD_SIMD_LOOP
  for (int lane = 0; lane < Lanes; ++lane) {
    const float ex = e1.x - chain.backX[lane];
    const float ey = e1.y - chain.backY[lane];
    const float ez = e1.z - chain.backZ[lane];
    // A zero sum vector (coincident points) gives Ebar = 0 and length 0.
    const float n2 = ex * ex + ey * ey + ez * ez;
    const float inv = 1.f / std::sqrt(std::max(n2, std::numeric_limits<float>::min()));
    length[lane] = n2 * inv;
    ux[lane] = ex * inv;
    uy[lane] = ey * inv;
    uz[lane] = ez * inv;
    // Edge 1 (v -> w) belongs to every candidate.
    const float norm1 = Norm::length(g1, ux[lane], uy[lane], uz[lane]);
    if constexpr (Measure == ChainMeasure::ProjectionWeighted)
      acc[lane] = (e1.x * ux[lane] + e1.y * uy[lane] + e1.z * uz[lane]) * norm1;
    else
      acc[lane] = norm1;
  }
  for (int j = 2; j <= chain.edgeCount; ++j) {
    const Vec3f ej = chain.edge[j];
    const typename Norm::EdgeParams& gj = chain.edgeNorm[j];
    STVD_SIMD_LOOP
    for (int lane = 0; lane < Lanes; ++lane) {
      const float normJ = Norm::length(gj, ux[lane], uy[lane], uz[lane]);
      if constexpr (Measure == ChainMeasure::ProjectionWeighted) {
        const float projection = ej.x * ux[lane] + ej.y * uy[lane] + ej.z * uz[lane];
        acc[lane] += j <= lane + 2 ? projection * normJ : 0.f;
      } else {
        acc[lane] = j <= lane + 2 ? std::max(acc[lane], normJ) : acc[lane];
      }
    }
  }
  STVD_SIMD_LOOP
  for (int lane = 0; lane < Lanes; ++lane) {
    if constexpr (Measure == ChainMeasure::ProjectionWeighted)
      out[lane] = std::max(acc[lane], 0.f);
    else
      out[lane] = length[lane] * acc[lane];
  }
}

template <class Domain, class Norm>
class Propagation {
 public:
  Propagation(const Domain& domain, const MetricField<Norm>& metric,
              const PropagationOptions& options)
      : domain_(domain),
        metric_(metric),
        options_(options),
        distance_(makeLargeArray<double>(domain.vertexCount(), kUnreachable)),
        predecessor_(makeLargeArray<VertexId>(domain.vertexCount(), kNoVertex)),
        queue_(domain.vertexCount()) {}

  PropagationResult run(const std::vector<VertexId>& sources) {
    for (const VertexId s : sources) {
      distance_[s] = 0.0;
      queue_.pushOrDecrease(s, 0.0);
    }
    std::vector<std::uint8_t> isTarget;
    std::size_t remainingTargets = 0;
    if (!options_.targets.empty()) {
      isTarget.assign(domain_.vertexCount(), 0);
      for (const VertexId t : options_.targets) {
        remainingTargets += isTarget[t] == 0 ? 1 : 0;
        isTarget[t] = 1;
      }
    }

    // STVD with k = 1 runs the vector code with an empty memory; that it
    // matches Dijkstra bit for bit is tested.
    const int k = options_.k;
    if (options_.method == Method::Dijkstra) {
      loop(isTarget, remainingTargets, [this](VertexId v) { relaxDijkstra(v); });
    } else if (options_.chainMeasure == ChainMeasure::ProjectionWeighted) {
      runVector<ChainMeasure::ProjectionWeighted>(k, isTarget, remainingTargets);
    } else {
      runVector<ChainMeasure::LargestEdgeNorm>(k, isTarget, remainingTargets);
    }

    // Only final vertices carry a distance; everything else is unreachable.
    for (VertexId v = 0; v < domain_.vertexCount(); ++v) {
      if (!queue_.isFinal(v)) {
        distance_[v] = kUnreachable;
        predecessor_[v] = kNoVertex;
      }
    }
    PropagationResult result;
    result.termination = termination_;
    result.finalizedVertices = finalized_;
    result.relaxedEdges = relaxed_;
    result.peakStateBytes = peakBytes_ + isTarget.capacity();
    result.distance = std::move(distance_);
    result.predecessor = std::move(predecessor_);
    return result;
  }

 private:
  template <ChainMeasure Measure>
  void runVector(int k, const std::vector<std::uint8_t>& isTarget, std::size_t remainingTargets) {
    if (k <= 5)
      loop(isTarget, remainingTargets, [this, k](VertexId v) { relaxVector<4, Measure>(v, k); });
    else if (k <= 9)
      loop(isTarget, remainingTargets, [this, k](VertexId v) { relaxVector<8, Measure>(v, k); });
    else
      loop(isTarget, remainingTargets, [this, k](VertexId v) { relaxVector<16, Measure>(v, k); });
  }

  template <class Relax>
  void loop(const std::vector<std::uint8_t>& isTarget, std::size_t remainingTargets,
            Relax&& relax) {
    constexpr std::uint64_t kProgressInterval = 1u << 16;
    PropagationProgress progress;
    progress.domainVertices = domain_.domainVertexCount();
    while (!queue_.empty()) {
      if (queue_.minKey() > options_.maxDistance) {
        termination_ = Termination::MaxDistanceReached;
        break;
      }
      const VertexId v = queue_.popMin();
      ++finalized_;
      if (!isTarget.empty() && isTarget[v] && --remainingTargets == 0) {
        termination_ = Termination::TargetsReached;
        break;
      }
      if (options_.progress && finalized_ % kProgressInterval == 0) {
        peakBytes_ = std::max(peakBytes_, stateBytes());
        progress.finalizedVertices = finalized_;
        progress.frontDistance = distance_[v];
        if (!options_.progress(progress)) {
          termination_ = Termination::Cancelled;
          break;
        }
      }
      relax(v);
    }
    peakBytes_ = std::max(peakBytes_, stateBytes());
  }

  std::uint64_t stateBytes() const {
    return distance_.capacity() * sizeof(double) + predecessor_.capacity() * sizeof(VertexId) +
           queue_.capacityBytes();
  }

  void update(VertexId w, VertexId v, double candidate) {
    if (candidate < distance_[w]) {
      distance_[w] = candidate;
      predecessor_[w] = v;
      queue_.pushOrDecrease(w, candidate);
    }
  }

  STVD_HOT_LOOP void relaxDijkstra(VertexId v) {
    const double dv = distance_[v];
    const auto& pv = metric_[v];
    domain_.forEachNeighbor(v, [&](VertexId w, Vec3f e) {
      if (queue_.isFinal(w)) return;
      ++relaxed_;
      // Norm::edgeParams(pv, metric_[w]) for domains in R^3; a surface
      // carries the norm into v's tangent frame (chain_unfolding.hpp).
      const auto g = ChainUnfolding<Domain>::template edgeNorm<Norm>(domain_, pv, metric_[w], v, w, e);
      update(w, v, dv + Norm::length(g, e.x, e.y, e.z));
    });
  }

  // STVD update of every neighbour w of v (see ChainMemory).
  template <int Lanes, ChainMeasure Measure>
  STVD_HOT_LOOP void relaxVector(VertexId v, int k) {
    VertexId chain[kMaxMemoryDepth];
    int count = 1;
    chain[0] = v;
    while (count < k && predecessor_[chain[count - 1]] != kNoVertex) {
      chain[count] = predecessor_[chain[count - 1]];
      ++count;
    }
    static_assert(Lanes <= ChainMemory<Norm>::kMaxLanes, "too many lanes");
    ChainMemory<Norm> memory;
    memory.edgeCount = count;
    Vec3f p[kMaxMemoryDepth];
    ChainUnfolding<Domain>::place(domain_, chain, count, p);
    for (int j = 2; j <= count; ++j) {
      memory.edge[j] = p[j - 2] - p[j - 1];
      // The norm in the unfolded frame (Norm::edgeParams of the end points
      // for domains in R^3; see chain_unfolding.hpp).
      memory.edgeNorm[j] = ChainUnfolding<Domain>::template edgeNorm<Norm>(
          domain_, metric_[chain[j - 1]], metric_[chain[j - 2]], chain[j - 1], chain[j - 2],
          memory.edge[j]);
    }
    // Padding lanes repeat the last chain vertex so that every lane stays
    // finite, and their base distance is +inf so that they never win.
    for (int lane = 0; lane < Lanes; ++lane) {
      const int c = std::min(lane + 1, count - 1);
      memory.backX[lane] = p[c].x;
      memory.backY[lane] = p[c].y;
      memory.backZ[lane] = p[c].z;
      memory.baseDistance[lane] = lane + 1 < count ? distance_[chain[lane + 1]] : kUnreachable;
    }

    const double dv = distance_[v];
    const auto& pv = metric_[v];
    domain_.forEachNeighbor(v, [&](VertexId w, Vec3f e1) STVD_ALWAYS_INLINE_LAMBDA {
      if (queue_.isFinal(w)) return;
      ++relaxed_;
      const typename Norm::EdgeParams g1 =
          ChainUnfolding<Domain>::template edgeNorm<Norm>(domain_, pv, metric_[w], v, w, e1);
      // i = 1 is the Dijkstra term, measured exactly as Dijkstra measures it
      // (so that k = 1 and Dijkstra agree bit for bit).
      double best = dv + Norm::length(g1, e1.x, e1.y, e1.z);
      alignas(64) float length[Lanes];
      chainSumLengths<Lanes, Measure, Norm>(memory, e1, g1, length);
      for (int lane = 0; lane < Lanes; ++lane)
        best = std::min(best, memory.baseDistance[lane] + static_cast<double>(length[lane]));
      update(w, v, best);
    });
  }

  const Domain& domain_;
  const MetricField<Norm>& metric_;
  const PropagationOptions& options_;
  std::vector<double> distance_;
  std::vector<VertexId> predecessor_;
  FrontQueue queue_;
  Termination termination_ = Termination::Completed;
  std::uint64_t finalized_ = 0;
  std::uint64_t relaxed_ = 0;
  std::uint64_t peakBytes_ = 0;
};

}  // namespace detail

template <class Domain, class Norm>
PropagationResult propagate(const Domain& domain, const MetricField<Norm>& metric,
                            const std::vector<VertexId>& sources,
                            const PropagationOptions& options) {
  if (metric.size() != domain.vertexCount())
    throw std::invalid_argument("metric has " + std::to_string(metric.size()) +
                                " vertices but the domain has " +
                                std::to_string(domain.vertexCount()));
  if (sources.empty()) throw std::invalid_argument("no source vertex given");
  for (const VertexId s : sources)
    if (!domain.contains(s))
      throw std::invalid_argument("source vertex " + std::to_string(s) +
                                  " lies outside the domain");
  for (const VertexId t : options.targets)
    if (!domain.contains(t))
      throw std::invalid_argument("target vertex " + std::to_string(t) +
                                  " lies outside the domain");
  if (options.method == Method::ShortTermVectorDijkstra &&
      (options.k < 1 || options.k > kMaxMemoryDepth))
    throw std::invalid_argument("STVD memory depth k = " + std::to_string(options.k) +
                                " is outside 1.." + std::to_string(kMaxMemoryDepth));
  if (std::isnan(options.maxDistance))
    throw std::invalid_argument("maximum distance is NaN");
  return detail::Propagation<Domain, Norm>(domain, metric, options).run(sources);
}

}  // namespace stvd
