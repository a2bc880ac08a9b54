// Definition of stvd::propagate. Include this header only to instantiate the
// propagation for a domain or a norm of your own; the built-in combinations
// are compiled in the library.
#pragma once

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "stvd/chain_unfolding.hpp"
#include "stvd/detail/front_queue.hpp"
#include "stvd/propagation.hpp"

namespace stvd {
namespace detail {

/// l_g(E_i) for several chain lengths i at once, one SIMD lane per i.
///
/// Lane L holds the candidate i = L + 2 with sum vector E_i (ex, ey, ez). The
/// chain edges are e[1..edgeCount] with edge norms g[1..edgeCount]; edge j
/// takes part in the sums with i >= j. Following section 6 of the paper,
///   l_g(E) = max(0, sum_j (e_j . Ebar) ||Ebar||_{g_j}),  Ebar = E / |E|:
/// E is split among the edges by their signed projections, and each portion
/// is measured with that edge's norm. A constant norm gives exactly
/// |E| ||Ebar|| = ||E||.
template <int Lanes, class Norm>
inline void chainSumLengths(const Vec3f* e, const typename Norm::EdgeParams* g, int edgeCount,
                            const float* ex, const float* ey, const float* ez, float* out) {
  alignas(64) float ux[Lanes], uy[Lanes], uz[Lanes], acc[Lanes];
  for (int lane = 0; lane < Lanes; ++lane) {
    const float n2 = ex[lane] * ex[lane] + ey[lane] * ey[lane] + ez[lane] * ez[lane];
    const float inv = n2 > 0.f ? 1.f / std::sqrt(n2) : 0.f;
    ux[lane] = ex[lane] * inv;
    uy[lane] = ey[lane] * inv;
    uz[lane] = ez[lane] * inv;
    acc[lane] = 0.f;
  }
  for (int j = 1; j <= edgeCount; ++j) {
    const Vec3f ej = e[j];
    const typename Norm::EdgeParams gj = g[j];
    for (int lane = 0; lane < Lanes; ++lane) {
      const float projection = ej.x * ux[lane] + ej.y * uy[lane] + ej.z * uz[lane];
      const float portion = projection * Norm::length(gj, ux[lane], uy[lane], uz[lane]);
      acc[lane] += (j <= lane + 2) ? portion : 0.f;
    }
  }
  for (int lane = 0; lane < Lanes; ++lane) out[lane] = acc[lane] > 0.f ? acc[lane] : 0.f;
}

template <class Domain, class Norm>
class Propagation {
 public:
  Propagation(const Domain& domain, const MetricField<Norm>& metric,
              const PropagationOptions& options)
      : domain_(domain),
        metric_(metric),
        options_(options),
        distance_(domain.vertexCount(), kUnreachable),
        predecessor_(domain.vertexCount(), kNoVertex),
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

    const int k = options_.method == Method::Dijkstra ? 1 : options_.k;
    if (k == 1) {
      loop(isTarget, remainingTargets, [this](VertexId v) { relaxDijkstra(v); });
    } else if (k <= 5) {
      loop(isTarget, remainingTargets, [this, k](VertexId v) { relaxVector<4>(v, k); });
    } else if (k <= 9) {
      loop(isTarget, remainingTargets, [this, k](VertexId v) { relaxVector<8>(v, k); });
    } else {
      loop(isTarget, remainingTargets, [this, k](VertexId v) { relaxVector<16>(v, k); });
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

  void relaxDijkstra(VertexId v) {
    const double dv = distance_[v];
    const auto& pv = metric_[v];
    domain_.forEachNeighbor(v, [&](VertexId w, Vec3f e) {
      if (queue_.isFinal(w)) return;
      ++relaxed_;
      update(w, v, dv + Norm::length(Norm::edgeParams(pv, metric_[w]), e.x, e.y, e.z));
    });
  }

  // STVD update of every neighbour w of v. The chain c_0 = v, c_1 = pred(v),
  // ... (at most k vertices, fewer near a source) is the same for all w, so
  // its positions, distances, edge vectors and edge norms are gathered once.
  template <int Lanes>
  void relaxVector(VertexId v, int k) {
    using EdgeParams = typename Norm::EdgeParams;
    VertexId chain[kMaxMemoryDepth];
    int count = 1;
    chain[0] = v;
    while (count < k && predecessor_[chain[count - 1]] != kNoVertex) {
      chain[count] = predecessor_[chain[count - 1]];
      ++count;
    }
    if (count == 1) {
      relaxDijkstra(v);
      return;
    }
    const int m = count - 1;  // candidates i = 2..count use lanes 0..m-1

    Vec3f p[kMaxMemoryDepth];
    ChainUnfolding<Domain>::place(domain_, chain, count, p);
    // Chain edge j >= 2 runs from c_{j-1} to c_{j-2}, in the direction of
    // propagation; e[1] and g[1] (edge v -> w) are filled per neighbour.
    Vec3f e[kMaxMemoryDepth + 1];
    EdgeParams g[kMaxMemoryDepth + 1];
    for (int j = 2; j <= count; ++j) {
      e[j] = p[j - 2] - p[j - 1];
      g[j] = Norm::edgeParams(metric_[chain[j - 1]], metric_[chain[j - 2]]);
    }
    // Padding lanes reuse the last chain vertex so that every lane stays finite.
    alignas(64) float ex[Lanes], ey[Lanes], ez[Lanes], length[Lanes];
    Vec3f back[Lanes];
    for (int lane = 0; lane < Lanes; ++lane) back[lane] = p[std::min(lane + 1, m)];

    const double dv = distance_[v];
    const auto& pv = metric_[v];
    domain_.forEachNeighbor(v, [&](VertexId w, Vec3f e1) {
      if (queue_.isFinal(w)) return;
      ++relaxed_;
      g[1] = Norm::edgeParams(pv, metric_[w]);
      e[1] = e1;
      // i = 1 is the Dijkstra term, measured exactly as Dijkstra measures it
      // (so that k = 1 and Dijkstra agree bit for bit).
      double best = dv + Norm::length(g[1], e1.x, e1.y, e1.z);
      for (int lane = 0; lane < Lanes; ++lane) {
        ex[lane] = e1.x - back[lane].x;  // E_i = x(w) - x(c_{i-1})
        ey[lane] = e1.y - back[lane].y;
        ez[lane] = e1.z - back[lane].z;
      }
      chainSumLengths<Lanes, Norm>(e, g, count, ex, ey, ez, length);
      for (int lane = 0; lane < m; ++lane)
        best = std::min(best, distance_[chain[lane + 1]] + static_cast<double>(length[lane]));
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
