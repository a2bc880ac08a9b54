// The propagation loop and its relaxations: the front is popped in key
// order (front_queue.hpp) and every vertex it finalises relaxes its
// neighbours, with the edge update of Dijkstra (relaxDijkstra) or the
// update of Short-Term Vector Dijkstra (relaxVector: the chain screen,
// chain_screen.hpp, then the candidates whose path stays in the domain;
// with the segment measure the best one becomes pending and is measured
// along its path when its vertex reaches the top of the queue, settleMin).
// Internal: propagation_definition.hpp defines propagate() with it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "stvd/metric/norms.hpp"
#include "stvd/propagation/candidate_path.hpp"
#include "stvd/propagation/detail/progress_hook.hpp"
#include "stvd/propagation/chain_unfolding.hpp"
#include "stvd/propagation/detail/chain_screen.hpp"
#include "stvd/propagation/detail/front_queue.hpp"
#include "stvd/propagation/detail/vertex_record.hpp"
#include "stvd/propagation/domain_hooks.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/system/large_array.hpp"

namespace stvd {
namespace detail {

/// A domain's CandidatePath, given the options where it takes them (a
/// surface checks the segment measure's lines only, and leaves the chain
/// rules as the paper defines them).
template <class Domain, class Norm>
CandidatePath<Domain, Norm> makeCandidatePath(const Domain& domain, const MetricField<Norm>& metric,
                                              const PropagationOptions& options) {
  if constexpr (std::is_constructible_v<CandidatePath<Domain, Norm>, const Domain&, const MetricField<Norm>&,
                                        const PropagationOptions&>)
    return CandidatePath<Domain, Norm>(domain, metric, options);
  else
    return CandidatePath<Domain, Norm>(domain, metric);
}

/// One run of propagate(). SegmentMeasure: ChainMeasure::Segment on a domain
/// that measures along paths, with deferred measurement and the 32-byte
/// record; otherwise Dijkstra or a chain rule, with the 16-byte record.
template <class Domain, class Norm, bool SegmentMeasure>
class Propagation {
  using VertexState = VertexRecord<SegmentMeasure>;

 public:
  Propagation(const Domain& domain, const MetricField<Norm>& metric,
              const PropagationOptions& options)
      : domain_(domain),
        metric_(metric),
        options_(options),
        state_(makeLargeArray<VertexState>(domain.vertexCount(), VertexState::unseen())),
        queue_(makeQueue(state_)),
        edgeMetric_(ChainUnfolding<Domain>::edgeMetric(domain, metric, options)),
        path_(makeCandidatePath(domain, metric, options)),
        lookup_(ChainUnfolding<Domain>::kEdgeNormIsMean && EdgeRuleIsMean<Norm>::value ? metric.sharedLookup()
                                                                                      : nullptr) {}

  PropagationResult run(const std::vector<VertexId>& sources) {
    // With start distances a listed source may be reached from another one
    // first (then it is no source of its distance): read the records.
    if (sources.size() < kFewSources && options_.sourceDistances.empty()) fewSources_ = sources;
    else fewSources_.assign(kFewSources, kNoVertex);  // size kFewSources: read the records
    for (std::size_t i = 0; i < sources.size(); ++i) {
      const VertexId s = sources[i];
      const double start = options_.sourceDistances.empty() ? 0.0 : options_.sourceDistances[i];
      if constexpr (SegmentMeasure) {
        if (start >= state_[s].measured) continue;  // a source given twice keeps its shortest start
        state_[s].measured = start;
        state_[s].open.key = start;
      } else {
        if (start >= state_[s].distance) continue;
        state_[s].distance = start;
      }
      queue_.pushOrDecrease(s, start);
    }
    if constexpr (SegmentMeasure && OffersSourceLines<CandidatePath<Domain, Norm>>::value) {
      if (path_.offersSourceLines() && sources.size() <= kFewSources) {
        for (std::size_t i = 0; i < sources.size(); ++i)
          sourceLines_.push_back({sources[i], options_.sourceDistances.empty() ? 0.0 : options_.sourceDistances[i]});
        withoutSourceLine_.assign(domain_.vertexCount(), 0);
      }
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
    const int k = memoryDepth<Domain>(options_);
    if constexpr (SegmentMeasure) {
      if (options_.segmentScreen == SegmentScreen::ChainMean && ChainUnfolding<Domain>::kEdgeNormIsMean &&
          EdgeRuleIsMean<Norm>::value)
        runVector<ChainScreen::ChainMean>(k, isTarget, remainingTargets);
      else
        runVector<ChainScreen::ProjectionWeighted>(k, isTarget, remainingTargets);
    } else if (options_.method == Method::Dijkstra) {
      loop(isTarget, remainingTargets, [this](VertexId v) { relaxDijkstra(v); });
    } else if (options_.chainMeasure == ChainMeasure::ProjectionWeighted) {
      runVector<ChainScreen::ProjectionWeighted>(k, isTarget, remainingTargets);
    } else {
      // LargestEdgeNorm, and the segment measure on a domain that cannot
      // measure along a path (CandidatePath), which falls back to the rule
      // that cannot go below the admissible bound.
      runVector<ChainScreen::LargestEdgeNorm>(k, isTarget, remainingTargets);
    }

    PropagationResult result;
    // Only final vertices carry a distance; everything else is unreachable.
    // The result arrays are written once in order, so they gain nothing from
    // huge pages, and on a virtual machine fresh huge pages can cost several
    // times more to touch first than small ones (docs/performance.md).
    result.distance = std::vector<double>(domain_.vertexCount(), kUnreachable);
    result.predecessor = std::vector<VertexId>(domain_.vertexCount(), kNoVertex);
    // A cancelled run holds no distances (PropagationOptions::progress).
    const VertexId filled = termination_ == Termination::Cancelled ? 0 : domain_.vertexCount();
    for (VertexId v = 0; v < filled; ++v) {
      if (queue_.isFinal(v)) {
        if (SegmentMeasure && state_[v].finalDistance() > options_.maxDistance) {
          --finalized_;  // settled a little beyond the limit: not reached
          continue;
        }
        result.distance[v] = state_[v].finalDistance();
        if constexpr (SegmentMeasure)
          result.predecessor[v] = state_[v].base;  // where its distance was measured from
        else
          result.predecessor[v] = state_[v].predecessor;
      }
    }
    result.termination = termination_;
    result.finalizedVertices = finalized_;
    result.relaxedEdges = relaxed_;
    result.measuredCandidates = measured_;
    result.refusedCandidates = refused_;
    // The records and the result arrays coexist while the latter are filled.
    peakBytes_ = std::max(peakBytes_, stateBytes() + result.distance.capacity() * sizeof(double) +
                                          result.predecessor.capacity() * sizeof(VertexId));
    result.peakStateBytes = peakBytes_ + isTarget.capacity();
    return result;
  }

 private:
  template <ChainScreen Screen>
  void runVector(int k, const std::vector<std::uint8_t>& isTarget, std::size_t remainingTargets) {
    loop(isTarget, remainingTargets, [this, k](VertexId v) { relaxVector<Screen>(v, k); });
  }

  template <class Relax>
  void loop(const std::vector<std::uint8_t>& isTarget, std::size_t remainingTargets,
            Relax&& relax) {
    ProgressHook hook(options_.progress, options_.interrupter, options_.progressInterval, "propagation");
    PropagationProgress progress;
    progress.domainVertices = domain_.domainVertexCount();
    if (hook.active() && !hook.report(progress)) {
      termination_ = Termination::Cancelled;
      return;
    }
    while (!queue_.empty()) {
      if (queue_.minKey() > options_.maxDistance) {
        // Segment measure: a key may be a screened estimate, and a candidate
        // screened above the limit may measure below it; measure it before
        // stopping, so that a limit at a full run's largest distance
        // completes that run. (A vertex settled a little beyond the limit is
        // reported unreachable, run(), so that a run with a limit finalises
        // what a full run finalises first.)
        bool stop = true;
        if constexpr (SegmentMeasure) {
          if (state_[queue_.minVertex()].open.pendingBase != kNoVertex) {
            if (!settleMin()) continue;  // queued again with its measured distance
            stop = state_[queue_.minVertex()].finalDistance() > options_.maxDistance;
          }
        }
        if (stop) {
          termination_ = Termination::MaxDistanceReached;
          break;
        }
      } else if constexpr (SegmentMeasure) {
        if (!settleMin()) continue;
      }
      const VertexId v = queue_.popMin();
      ++finalized_;
      if (!queue_.empty()) {
        prefetchNeighborhood(queue_.minVertex());
        if constexpr (SegmentMeasure) prefetchPending(queue_.minVertex());
      }
      if (!isTarget.empty() && isTarget[v] && --remainingTargets == 0) {
        termination_ = Termination::TargetsReached;
        break;
      }
      if (hook.due(finalized_)) {
        peakBytes_ = std::max(peakBytes_, stateBytes());
        progress.finalizedVertices = finalized_;
        progress.frontDistance = state_[v].finalDistance();
        progress.fraction = double(finalized_) / double(std::max<std::uint64_t>(progress.domainVertices, 1));
        if (!hook.report(progress)) {
          termination_ = Termination::Cancelled;
          break;
        }
      }
      relax(v);
      if (options_.method != Method::Dijkstra && !queue_.empty()) prefetchChain(queue_.minVertex());
    }
    peakBytes_ = std::max(peakBytes_, stateBytes());
    if (hook.active() && termination_ != Termination::Cancelled) {
      progress.finalizedVertices = finalized_;
      progress.fraction = 1.0;
      hook.report(progress);  // the work is done: a late cancel changes nothing
    }
  }

  // The vertex now at the top of the queue is nearly always the next one
  // popped. Asking for its neighbours' records and tensors (and what the
  // domain reads to form their edge vectors) while v is relaxed overlaps
  // the cache misses of the two pops.
  STVD_ALWAYS_INLINE void prefetchNeighborhood(VertexId u) {
    if constexpr (kPrefetches) {
      domain_.forEachNeighborRun(u, [&](VertexId first, VertexId last) {
        prefetchRange(&state_[first], &state_[last]);
        prefetchRange(&metric_[first], &metric_[last]);
        if constexpr (SegmentMeasure) prefetchRange(queue_.slotAddress(first), queue_.slotAddress(last));
      });
      domain_.prefetchNeighborGeometry(u);
    }
  }

  // The next vertex will most likely be settled next: when it has a pending
  // candidate, its base's record (long out of cache: the candidate was found
  // when the front was one edge behind) and what the path asks for ahead of
  // the measurement (a tetrahedral mesh the start of its walk; a grid
  // nothing, see VoxelGridCandidatePath::prefetchSegment) are asked for
  // while the current vertex is relaxed.
  STVD_ALWAYS_INLINE void prefetchPending(VertexId u) {
    if constexpr (!CandidatePath<Domain, Norm>::usesPlacedChain()) {
      const VertexId base = state_[u].open.pendingBase;
      if (base == kNoVertex) return;
      detail::prefetch(&state_[base]);
      path_.prefetchSegment(base, u);
    }
  }

  // STVD also reads the predecessor chain of the next vertex u: dependent
  // loads reaching k - 1 voxels behind the front, into voxels popped long
  // ago. With deferred measurement the chain is in two records (see
  // VertexRecord<true>). Otherwise, once u's neighbourhood has arrived
  // (after v's relaxation), the first two links are known; the rest of the
  // chain is guessed to go on by the second link's offset, as it does where
  // the front is straight. Only a grid's numbering makes that guess
  // meaningful (DomainHooks::kChainContinuesAlongStep).
  STVD_ALWAYS_INLINE void prefetchChain(VertexId u) {
    if constexpr (SegmentMeasure) {
      // Here the chain is known exactly: c_1's record (one of u's
      // neighbours, asked for with them) holds c_2 onwards.
      const VertexState& su = state_[u];
      if (anyAngle_ > 0 && su.base != kNoVertex) {
        // Its any-angle ancestor, most likely the vertex it will be final
        // with (its chain of edges holds it already where it is near).
        detail::prefetch(&state_[su.base]);
        detail::prefetch(&metric_[su.base]);
      }
      const VertexId p1 = su.predecessor;
      if (p1 == kNoVertex) return;
      const VertexState& s1 = state_[p1];
      const int k = memoryDepth<Domain>(options_);
      for (int l = 2; l < k && l < 3 + VertexState::kStoredAncestors; ++l) {
        const VertexId c = l == 2 ? s1.predecessor : s1.ancestors[l - 3];
        if (c == kNoVertex) break;
        detail::prefetch(&state_[c]);
        detail::prefetch(&metric_[c]);
      }
    } else if constexpr (DomainHooks<Domain>::kChainContinuesAlongStep) {
      const VertexId p1 = state_[u].predecessor;
      if (p1 == kNoVertex) return;
      const VertexId p2 = state_[p1].predecessor;
      if (p2 == kNoVertex) return;
      const std::int64_t step = static_cast<std::int64_t>(p2) - static_cast<std::int64_t>(p1);
      const std::int64_t count = static_cast<std::int64_t>(state_.size());
      std::int64_t guess = p2;
      for (int m = 2; m < memoryDepth<Domain>(options_) && guess >= 0 && guess < count; ++m, guess += step) {
        detail::prefetch(&state_[static_cast<std::size_t>(guess)]);
        detail::prefetch(&metric_[static_cast<std::size_t>(guess)]);
      }
    }
  }

  std::uint64_t stateBytes() const {
    std::uint64_t bytes = state_.capacity() * sizeof(VertexState) + queue_.capacityBytes();
    if constexpr (OffersSourceLines<CandidatePath<Domain, Norm>>::value) bytes += withoutSourceLine_.capacity();
    return bytes;
  }

  void update(VertexId w, VertexId v, double candidate) {
    VertexState& sw = state_[w];
    if (candidate < sw.distance) {
      sw.distance = candidate;
      sw.predecessor = v;
      queue_.pushOrDecrease(w, candidate);
    }
  }

  // Gathers the neighbours of v that are not final, with their edge vector
  // and edge norm, in batches; `flush` computes and applies the candidates
  // of a full batch (and of the last one). ByLookup: where the metric has a
  // shared lookup (lookup_), the batch keeps the end points' parameters to
  // measure by lookup instead of the edge norms (NeighborBatch::lookup);
  // asked for where only Dijkstra's candidates and the chain-mean screen
  // are computed.
  template <bool ByLookup, class Flush>
  STVD_ALWAYS_INLINE void forEachNeighborBatch(VertexId v, NeighborBatch<Norm>& batch,
                                               Flush&& flush) {
    const auto& pv = metric_[v];
    batch.size = 0;
    constexpr bool kMayLookUp = ByLookup && TableLookup<Norm>::value;
    const bool byLookup = kMayLookUp && lookup_ != nullptr;
    if constexpr (kMayLookUp) {
      if (byLookup) batch.beginByLookup(lookup_, &metric_[0], v);
    }
    domain_.forEachNeighbor(v, [&](VertexId w, Vec3f e) STVD_ALWAYS_INLINE_LAMBDA {
      if (queue_.isFinal(w)) return;
      if (kMayLookUp && byLookup) {
        batch.addByLookup(w, e);
      } else {
        // Norm::edgeParams(pv, metric_[w]) for domains in R^3; a surface
        // carries the norm into v's tangent frame (chain_unfolding.hpp).
        batch.add(w, e, ChainUnfolding<Domain>::template edgeNorm<Norm>(domain_, edgeMetric_, pv, metric_[w], v, w, e));
      }
      if (batch.size == NeighborBatch<Norm>::kCapacity) {
        batch.pad();
        flush(batch);
        batch.size = 0;
      }
    });
    if (batch.size > 0) {
      batch.pad();
      flush(batch);
    }
  }

  STVD_ALWAYS_INLINE void applyCandidates(VertexId v, const NeighborBatch<Norm>& batch) {
    relaxed_ += static_cast<std::uint64_t>(batch.size);
    for (int n = 0; n < batch.size; ++n) update(batch.vertex[n], v, batch.best[n]);
  }

  STVD_HOT_LOOP void relaxDijkstra(VertexId v) {
    const double dv = state_[v].finalDistance();
    NeighborBatch<Norm> batch;
    forEachNeighborBatch<true>(v, batch, [&](NeighborBatch<Norm>& b) STVD_ALWAYS_INLINE_LAMBDA {
      b.setDijkstraCandidates(dv);
      measureLongSteps(v, b, dv);
      applyCandidates(v, b);
    });
  }

  // The Dijkstra terms of stencil steps longer than one voxel step, measured
  // along them where the path offers it (VoxelGridCandidatePath::
  // measuresLongSteps).
  STVD_ALWAYS_INLINE void measureLongSteps(VertexId v, NeighborBatch<Norm>& batch, double dv) const {
    if constexpr (OffersLongSteps<CandidatePath<Domain, Norm>>::value) {
      if (path_.measuresLongSteps()) measureLongStepsOf(v, batch, dv);
    } else {
      (void)v;
      (void)batch;
      (void)dv;
    }
  }
  // Out of line, so that the default's relaxation (26-neighbourhood, where
  // it never runs) does not carry the measurement's code.
  // (Instantiated only for paths that offer long steps.)
  __attribute__((noinline)) void measureLongStepsOf(VertexId v, NeighborBatch<Norm>& batch, double dv) const {
    for (int n = 0; n < batch.size; ++n) {
      const float length = path_.longStepLength(v, batch.vertex[n]);
      if (length >= 0.f) batch.best[n] = dv + static_cast<double>(length);
    }
  }

  // The predecessor chain c_0 = v, c_1 = pred(v), ... of the vertex v just
  // finalised, at most k vertices; returns their count. With deferred
  // measurement it first stores v's ancestors in its record (see
  // VertexRecord<true>), taken from its predecessor's, which was relaxed
  // before v could have it as predecessor.
  STVD_ALWAYS_INLINE int gatherChain(VertexId v, int k, VertexId* chain) {
    chain[0] = v;
    int count = 1;
    if constexpr (SegmentMeasure) {
      constexpr int kStored = VertexState::kStoredAncestors;
      VertexState& sv = state_[v];
      const VertexId p1 = sv.predecessor;
      VertexId stored[kStored + 1];
      if (p1 == kNoVertex) {
        std::fill(stored, stored + kStored + 1, kNoVertex);
      } else {
        const VertexState& s1 = state_[p1];
        stored[0] = s1.predecessor;
        for (int a = 1; a <= kStored; ++a) stored[a] = s1.ancestors[a - 1];
        if (count < k) chain[count++] = p1;
        for (int a = 0; a <= kStored && count < k && stored[a] != kNoVertex; ++a) chain[count++] = stored[a];
      }
      for (int a = 0; a < kStored; ++a) sv.ancestors[a] = stored[a];
    }
    while (count < k && state_[chain[count - 1]].predecessor != kNoVertex) {
      chain[count] = state_[chain[count - 1]].predecessor;
      ++count;
    }
    return count;
  }

  // Appends v's first anyAngle_ any-angle ancestors that its chain of
  // `count` vertices does not hold (VertexRecord<true>::base: where v's
  // distance was measured from, then where that vertex's was, ...), while
  // they lie within reach of v (a source within the source reach): each
  // becomes one more candidate base for v's neighbours. Returns the new
  // count.
  STVD_ALWAYS_INLINE int appendAnyAngleAncestors(VertexId v, VertexId* chain, int count) {
    if constexpr (SegmentMeasure && kAnyAngle) {
      const int latticeCount = count;
      VertexId a = state_[v].base;
      // An ancestor in the chain already is passed over, a few times at
      // most: where a lattice vertex on the straight line from the source
      // tied with the source, this still reaches the source.
      for (int hop = 0; hop < anyAngle_ + kPassedOver && count - latticeCount < anyAngle_ && a != kNoVertex;
           ++hop) {
        const VertexState& sa = state_[a];
        bool inChain = false;
        for (int j = 1; j < latticeCount; ++j) inChain = inChain || chain[j] == a;
        if (!inChain) {
          const bool source = sa.base == kNoVertex;
          const int reach = source && nearMetric(v, a, kSourceMetricTolerance) ? sourceReach_ : segmentReach_;
          if (path_.steps(v, a) > reach) break;
          // Nor past a change of the metric: see kAncestorMetricTolerance.
          if (!source && !nearMetric(v, a, kAncestorMetricTolerance)) break;
          chain[count++] = a;
        }
        a = sa.base;
      }
      // Source factoring: the source that v's ancestors lead to next is a
      // candidate too, within the source reach, however many ancestors came
      // before it (on a constant metric the segment from the source is exact,
      // and a lattice vertex on the straight line from it that tied with it
      // must not hide it).
      if (anyAngle_ > 0 && a != kNoVertex && isSource(a) && path_.steps(v, a) <= sourceReach_ &&
          nearMetric(v, a, kSourceMetricTolerance)) {
        bool inChain = false;
        for (int j = 1; j < count; ++j) inChain = inChain || chain[j] == a;
        if (!inChain) chain[count++] = a;
      }
    }
    return count;
  }
  static constexpr int kPassedOver = 2;

  // Whether the final vertex v is a source of its distance (one that was
  // measured from no vertex: a source, with its start distance, that no
  // other source reached first): from the few sources of a run without
  // reading v's record (a cache miss at the front), else from its record.
  STVD_ALWAYS_INLINE bool isSource(VertexId v) const {
    if (fewSources_.size() < kFewSources) {
      for (const VertexId s : fewSources_) if (s == v) return true;
      return false;
    }
    return state_[v].base == kNoVertex;
  }
  static constexpr std::size_t kFewSources = 16;

  // Whether the norm at v is within `tolerance` of the one at s: the
  // relative (Euclidean) difference of the norm's parameters (a tensor's six
  // entries; a norm whose parameters are not the norm's own, a lattice
  // table's, runs no any-angle ancestors or source factoring:
  // ExactInEveryDirection).
  STVD_ALWAYS_INLINE bool nearMetric(VertexId v, VertexId s, float tolerance) const {
    constexpr int kFloats = ChainMemory<Norm>::kNormFloats;
    float a[kFloats], b[kFloats];
    std::memcpy(a, &metric_[v], sizeof a);
    std::memcpy(b, &metric_[s], sizeof b);
    float difference = 0.f, size = 0.f;
    for (int f = 0; f < kFloats; ++f) {
      difference += (a[f] - b[f]) * (a[f] - b[f]);
      size += b[f] * b[f];
    }
    return difference <= tolerance * tolerance * size;
  }
  // The relative (Frobenius) difference of the parameters below which a
  // vertex counts as near its source's metric: the region where the
  // straight segment from the source is a candidate beyond the segment
  // reach (source factoring, as fast marching factors the distance near a
  // seed with the seed's metric). On the curved scene of
  // bench/propagation_speed.cpp (shear slope 0.49, 128^3), with the source
  // reach at 64 steps: 0.05 costs 3.3 times Dijkstra (mean error 1.58 %),
  // 0.1 or 0.2 3.4 to 3.7 times (1.52 %), no limit 5.7 times; a constant
  // metric is exact within the source reach with any of them.
  static constexpr float kSourceMetricTolerance = 0.05f;
  // The same for an any-angle ancestor a of v: the walk stops at the first
  // ancestor whose metric differs from v's by more. Where the metric
  // changes from voxel to voxel (real DTI) a long segment measured from a
  // distant ancestor ran through other tensors than the chain of edges
  // follows, and widened the brain's band against Lanthier M = 8 beyond the
  // chain alone's (p5..p95 -1.52..+2.56 % against -1.43..+2.42 %); with 0.1
  // it is -1.40..+2.41 %. On constant metrics nothing changes; on the
  // curved scene (gamma 20) mean / p99 / largest 64^3 1.31 / 20.2 / 35.8 ->
  // 1.25 / 18.6 / 35.4 %, 128^3 0.932 / 11.7 / 27.7 -> 0.941 / 11.6 / 27.7 %.
  // A source within the segment reach stays a candidate whatever its metric
  // (the rule applied to it too: curved 32^3 largest 62.4 -> 73.4 %, brain
  // -1.43..+2.43 %). docs/accuracy.md, "Ancestors only where the metric is
  // near the relaxed vertex's".
  static constexpr float kAncestorMetricTolerance = 0.1f;
  std::vector<VertexId> fewSources_;

  // STVD update of every neighbour w of v (see ChainMemory): the screen
  // ranks the candidates; with a chain rule (Measured false) the screened
  // value is the candidate's length, otherwise the best candidate that could
  // still win is measured along its path. Either way a candidate whose path
  // leaves the domain is refused and the next one tried.
  template <ChainScreen Screen>
  STVD_HOT_LOOP void relaxVector(VertexId v, int k) {
    VertexId chain[kMaxChainLength];
    const int latticeCount = gatherChain(v, k, chain);
    const int count = appendAnyAngleAncestors(v, chain, latticeCount);
    ChainMemory<Norm> memory;
    memory.edgeCount = count;
    memory.latticeLanes = latticeCount - 1;
    Vec3f p[kMaxChainLength];
    ChainUnfolding<Domain>::place(domain_, chain, count, p);
    // The chain's edges and their norms, which the two chain rules measure
    // with (the chain-mean screen needs only the vertices' norms).
    if constexpr (Screen != ChainScreen::ChainMean) {
      for (int j = 2; j <= latticeCount; ++j) {
        memory.edge[j] = p[j - 2] - p[j - 1];
        // The norm in the unfolded frame (Norm::edgeParams of the end points
        // for domains in R^3; see chain_unfolding.hpp).
        memory.edgeNorm[j] = ChainUnfolding<Domain>::template edgeNorm<Norm>(
            domain_, edgeMetric_, metric_[chain[j - 1]], metric_[chain[j - 2]], chain[j - 1], chain[j - 2],
            memory.edge[j]);
      }
    }
    for (int lane = 0; lane + 1 < count; ++lane) {
      memory.backX[lane] = p[lane + 1].x;
      memory.backY[lane] = p[lane + 1].y;
      memory.backZ[lane] = p[lane + 1].z;
      memory.baseDistance[lane] = state_[chain[lane + 1]].finalDistance();
    }
    if constexpr (Screen == ChainScreen::ChainMean) {
      std::memcpy(memory.vertexNorm, &metric_[v], sizeof memory.vertexNorm);
      constexpr int kFloats = ChainMemory<Norm>::kNormFloats;
      float sum[kFloats];
      std::memcpy(sum, &metric_[v], sizeof sum);
      for (int lane = 0; lane + 1 < latticeCount; ++lane) {
        float c[kFloats];
        std::memcpy(c, &metric_[chain[lane + 1]], sizeof c);
        for (int f = 0; f < kFloats; ++f) sum[f] += c[f];
        std::memcpy(memory.chainNormSum[lane], sum, sizeof sum);
      }
    }
    const double dv = state_[v].finalDistance();
    // An any-angle ancestor b is screened as the segment from b under the
    // edge rule of v's and b's norms, times the ratio of what v's path from
    // b measured (dist(v) - dist(b)) to what that norm gives the segment
    // b -> v: exact for a constant metric and for a neighbour w in line with
    // b and v, and above the segment's length where v's path from b bends.
    for (int lane = latticeCount - 1; lane + 1 < count; ++lane) {
      const int a = lane - (latticeCount - 1);
      memory.ancestorNorm[a] = Norm::edgeParams(metric_[v], metric_[chain[lane + 1]]);
      const float straight = Norm::length(memory.ancestorNorm[a], -p[lane + 1].x, -p[lane + 1].y, -p[lane + 1].z);
      const double travelled = dv - memory.baseDistance[lane];
      memory.ancestorRatio[a] = straight > 0.f && travelled > 0.0 ? static_cast<float>(travelled / straight) : 1.f;
    }
    path_.beginChain(chain, count, p);
    const bool mayRefuse = path_.mayRefuse();

    NeighborBatch<Norm> batch;
    forEachNeighborBatch<Screen == ChainScreen::ChainMean>(v, batch, [&](NeighborBatch<Norm>& b)
                                                                 STVD_ALWAYS_INLINE_LAMBDA {
      // i = 1 is the Dijkstra term, measured exactly as Dijkstra measures it.
      b.setDijkstraCandidates(dv);
      measureLongSteps(v, b, dv);
      if constexpr (SegmentMeasure) {
        if (count == 1) keepDijkstraTerms(v, b);
      }
      if (count > 1) {
        CandidateScreen<Norm> screen;
        screenChainCandidates<Screen>(memory, b, screen);
        if (count > latticeCount) screenAnyAngleAncestors(memory, b, screen);
        if constexpr (SegmentMeasure)
          keepBestScreenedCandidates(v, memory, b, screen, mayRefuse);
        else if (mayRefuse)
          acceptBestCandidates(memory, b, screen);
        else
          lowerToScreenedCandidates(memory, b, screen);
      }
      if constexpr (SegmentMeasure)
        applyDeferred(v, b, chain);
      else
        applyCandidates(v, b);
    });
  }

  // The reach of an any-angle ancestor (a source when `source`): the
  // option, or the domain's default.
  int reachOption(const std::optional<int>& option, bool source) const {
    if constexpr (SegmentMeasure && kAnyAngle) {
      if (option) return *option;
      return source ? path_.defaultSourceReach() : path_.defaultReach();
    } else {
      (void)option;
      (void)source;
      return 0;
    }
  }

  // The lane (candidate i = lane + 2) with the smallest screened value
  // among those not tried yet, or -1.
  STVD_ALWAYS_INLINE static int bestUntriedLane(const ChainMemory<Norm>& memory,
                                                const CandidateScreen<Norm>& screen, int n,
                                                unsigned tried, double& value) {
    int best = -1;
    value = kUnreachable;
    for (int lane = 0; lane + 2 <= memory.edgeCount; ++lane) {
      if ((tried >> lane) & 1u) continue;
      const double candidate = memory.baseDistance[lane] + static_cast<double>(screen.length[lane][n]);
      if (candidate < value) {
        value = candidate;
        best = lane;
      }
    }
    return best;
  }

  // Chain rules near the domain's boundary: the best screened candidate
  // whose path stays in the domain.
  STVD_ALWAYS_INLINE void acceptBestCandidates(const ChainMemory<Norm>& memory, NeighborBatch<Norm>& batch,
                            const CandidateScreen<Norm>& screen) {
    for (int n = 0; n < batch.size; ++n) {
      unsigned tried = 0;
      double value;
      for (int lane; (lane = bestUntriedLane(memory, screen, n, tried, value)) >= 0;) {
        if (!(value < batch.best[n])) break;
        tried |= 1u << lane;
        if (path_.accepts(lane + 2, batch.vertex[n])) {
          batch.best[n] = value;
          break;
        }
        ++refused_;
      }
    }
  }

  // ChainMeasure::Segment, deferred measurement (SegmentMeasure = true).
  // Measuring a candidate along its path costs several times its screen,
  // and a vertex is relaxed from a dozen neighbours whose best candidates
  // differ by fractions of a percent, so measuring at every relaxation would
  // measure nearly all of them (measured: 8 to 12 per vertex). Instead a
  // relaxation only screens: the Dijkstra term is exact and lowers the
  // vertex's measured distance (VertexRecord<true>::measured); the best
  // screened candidate, when its screened value is below everything the
  // vertex has, becomes its pending candidate, and that screened value its
  // key in the queue. When the vertex reaches the top of the queue, the
  // pending candidate is measured along its path (settleMin) and the vertex
  // is queued again with its measured distance; it is finalised only when
  // it reaches the top with nothing pending. So each vertex is measured
  // about once, and every distance it is finalised with is a measured one.

  // Records each neighbour's Dijkstra term as measured, and its best
  // screened candidate that stays in the domain as pending: best[n] becomes
  // the neighbour's new key, and pendingLane[n] says which candidate it is.
  STVD_ALWAYS_INLINE void keepBestScreenedCandidates(VertexId v, const ChainMemory<Norm>& memory,
                                                     NeighborBatch<Norm>& batch,
                                                     const CandidateScreen<Norm>& screen, bool mayRefuse) {
    alignas(64) double value[NeighborBatch<Norm>::kCapacity];
    alignas(64) int lane[NeighborBatch<Norm>::kCapacity];
    bestScreenedCandidates(memory, batch, screen, value, lane);
    for (int n = 0; n < batch.size; ++n) {
      const VertexId w = batch.vertex[n];
      offerSourceLines(w, v, batch.best[n]);
      keepMeasured(state_[w], batch.best[n], v, v);
      batch.pendingLane[n] = -1;
      // A candidate not below what w has (its Dijkstra term, or its key)
      // cannot become pending: no need to check its path.
      const double limit = std::min(batch.best[n], state_[w].open.key);
      if (!(value[n] < limit)) continue;
      if (measuresWhileChecking(path_)) {
        // Checking the paths measured them: every candidate is measured now,
        // and the shortest becomes a measured distance; nothing is pending.
        const Vec3f e{batch.ex[n], batch.ey[n], batch.ez[n]};
        double shortest = kUnreachable;
        for (int l = 0; l + 2 <= memory.edgeCount; ++l) {
          const float length = path_.length(l + 2, w, e);
          if (length == kRefusedCandidate) {
            ++refused_;
            continue;
          }
          ++measured_;
          shortest = std::min(shortest, memory.baseDistance[l] + static_cast<double>(length));
        }
        keepMeasured(state_[w], shortest, v, v);
        batch.best[n] = std::min(batch.best[n], shortest);
        continue;
      }
      if (!mayRefuse || path_.accepts(lane[n] + 2, w)) {
        batch.best[n] = value[n];
        batch.pendingLane[n] = lane[n];
        continue;
      }
      // Near the domain's boundary: the next best candidates in turn.
      ++refused_;
      unsigned tried = 1u << lane[n];
      double next;
      for (int l; (l = bestUntriedLane(memory, screen, n, tried, next)) >= 0;) {
        if (!(next < limit)) break;
        tried |= 1u << l;
        if (path_.accepts(l + 2, w)) {
          batch.best[n] = next;
          batch.pendingLane[n] = l;
          break;
        }
        ++refused_;
      }
    }
  }

  // Keeps `value`, measured from `base` by the relaxation of w's neighbour
  // `link`, when it is w's shortest so far.
  STVD_ALWAYS_INLINE static void keepMeasured(VertexState& s, double value, VertexId base, VertexId link) {
    if (value < s.measured) {
      s.measured = value;
      s.base = base;
      s.open.link = link;
    }
  }

  // Source factoring where the candidates are not segments from stored
  // ancestors (a surface, OffersSourceLines): when w is first reached, the
  // line from w straight to each source of a run with few sources, where the
  // domain has one, lowers `best` to its length from that source's start.
  // On a flat part of a surface under a constant metric that line is the
  // geodesic, which the chain of edges' candidates reach only where the
  // chain happens to run along it (docs/surfaces.md). The neighbours of a
  // source are first reached from the source itself (keepDijkstraTerms),
  // whose line to them is their edge. A vertex first reached from a
  // neighbour v that had no line walks none either: beyond the walk's reach
  // (SurfaceCandidatePath::kMaxSourceLineFaces), past a fold or in a hole's
  // shadow the neighbour's line ended, and walking each vertex's line there
  // until it ends made the isotropic 200 x 200 plane of
  // bench/surface_speed.cpp (k = 8) 3.3 times slower than without source
  // lines (255 against 78 ms; 90 ms with this rule).
  STVD_ALWAYS_INLINE void offerSourceLines(VertexId w, VertexId v, double& best) {
    if constexpr (OffersSourceLines<CandidatePath<Domain, Norm>>::value) {
      if (sourceLines_.empty() || state_[w].measured != kUnreachable) return;
      withoutSourceLine_[w] = withoutSourceLine_[v] || !offerSourceLinesOf(w, best);
    } else {
      (void)w;
      (void)v;
      (void)best;
    }
  }
  // Whether some source's line to w exists. (Instantiated only for paths
  // that offer source lines.)
  __attribute__((noinline)) bool offerSourceLinesOf(VertexId w, double& best) {
    bool any = false;
    for (const SourceLine& source : sourceLines_) {
      const float length = path_.sourceLineLength(w, source.vertex);
      if (length == kRefusedCandidate) continue;
      ++measured_;
      any = true;
      best = std::min(best, source.start + static_cast<double>(length));
    }
    return any;
  }

  // A chain of one vertex (a source) has no candidate beyond the Dijkstra term.
  STVD_ALWAYS_INLINE void keepDijkstraTerms(VertexId v, NeighborBatch<Norm>& batch) {
    for (int n = 0; n < batch.size; ++n) {
      keepMeasured(state_[batch.vertex[n]], batch.best[n], v, v);
      batch.pendingLane[n] = -1;
    }
  }

  STVD_ALWAYS_INLINE void applyDeferred(VertexId v, const NeighborBatch<Norm>& batch, const VertexId* chain) {
    relaxed_ += static_cast<std::uint64_t>(batch.size);
    for (int n = 0; n < batch.size; ++n) {
      const VertexId w = batch.vertex[n];
      VertexState& sw = state_[w];
      if (batch.best[n] < sw.open.key) {
        sw.open.key = batch.best[n];
        sw.predecessor = v;
        const int lane = batch.pendingLane[n];
        sw.open.pendingBase = lane < 0 ? kNoVertex : chain[lane + 1];
        queue_.pushOrDecrease(w, batch.best[n]);
      }
    }
  }

  // Measures the pending candidate of w (from its predecessor v) along its
  // path and keeps it when it is shorter than what w has measured.
  STVD_HOT_LOOP void measurePending(VertexId w, VertexState& sw) {
    const VertexId v = sw.predecessor, base = sw.open.pendingBase;
    sw.open.pendingBase = kNoVertex;
    float l;
    if constexpr (CandidatePath<Domain, Norm>::usesPlacedChain()) {
      // The path depends on the chain between c_{i-1} and v (a surface's
      // unfolding): rebuild it.
      VertexId chain[kMaxChainLength];
      int i = 1;
      chain[0] = v;
      while (chain[i - 1] != base) {
        chain[i] = state_[chain[i - 1]].predecessor;
        ++i;
      }
      Vec3f p[kMaxChainLength];
      ChainUnfolding<Domain>::place(domain_, chain, i, p);
      path_.beginChain(chain, i, p);
      l = path_.length(i, w, ChainUnfolding<Domain>::neighborEdge(domain_, v, w));
    } else {
      l = path_.segmentLength(base, w);
    }
    if (l == kRefusedCandidate) {
      ++refused_;
      return;
    }
    ++measured_;
    // Measured from `base` along a straight segment; a surface's line runs
    // across faces, so there the result keeps the neighbour v as the
    // predecessor (its chain of edges is what the unfolding needs). Either
    // way the chain of edges goes on through v.
    keepMeasured(sw, state_[base].measured + static_cast<double>(l), kAnyAngle ? base : v, v);
  }

  // How far above its screened key a measured distance may lie for the
  // vertex to be finalised without going back into the queue.
  static constexpr double kSettleSlack = 0.01;

  // Makes the vertex at the top of the queue ready to be finalised: true
  // when its key is a measured distance. Otherwise its pending candidate is
  // measured along its path, the vertex is queued again with the shortest
  // measured distance it has, and false is returned (the top has changed).
  bool settleMin() {
    const VertexId w = queue_.minVertex();
    VertexState& sw = state_[w];
    if (queue_.minKey() < sw.open.key) {
      // An entry left from a lower key that the vertex had before its key
      // was raised (requeueMin below, into a later bucket): the front queue
      // takes a cold vertex's lowest entry for its key, as keys only fall
      // there (FrontQueue::requeueMin). Queue the vertex with its own key.
      // Measured and settled at this entry instead, it was finalised out of
      // order whenever the buckets had left the old entry behind, and where
      // the buckets lie depends on the whole front: a multi-source run then
      // differed from its single-source runs far from where the fronts meet
      // (multi_source_test.cpp).
      queue_.requeueMin(sw.open.key);
      return false;
    }
    if (sw.open.pendingBase != kNoVertex) {
      measurePending(w, sw);
      // A screen that was only a little too low (or too high: the measured
      // distance is then the vertex's smallest) leaves the vertex where it
      // is: it is finalised at once with its measured distance. Requeueing
      // it would move it down the heap and bring it up again later, cold:
      // measured on the curved scene at 128^3, that cost k = 8 a third of
      // its time and gained no accuracy (1.13 % against 1.09 % mean error).
      // STVD's front is not in exact order of distance anyway
      // (docs/architecture.md).
      if (sw.measured <= queue_.minKey() * (1.0 + kSettleSlack)) {
        sw.open.key = sw.measured;
        sw.predecessor = sw.open.link;  // the chain goes on through what gave the distance
        return true;
      }
    } else {
      sw.predecessor = sw.open.link;
      return true;  // measured, and queued with that distance
    }
    // The vertex's key was a screened estimate well below its measured
    // distance: queue it with its measured distance.
    sw.open.key = sw.measured;
    sw.predecessor = sw.open.link;
    queue_.requeueMin(sw.measured);
    return false;
  }

  const Domain& domain_;
  const MetricField<Norm>& metric_;
  const PropagationOptions& options_;
  // FrontQueue finds the slot of vertex v at word v << kRecordWordsLog2
  // from the first record's slot; the segment measure's records leave their
  // slots to the queue's own array (VertexRecord<true>).
  static constexpr unsigned kRecordWordsLog2 = SegmentMeasure ? 3 : 2;
  static_assert(sizeof(VertexState) == sizeof(std::uint32_t) << kRecordWordsLog2,
                "one record per 16 or 32 bytes");
  static FrontQueue makeQueue(std::vector<VertexState>& state) {
    if constexpr (SegmentMeasure)
      return FrontQueue(state.size());
    else
      return FrontQueue(&state.data()->queueSlot, kRecordWordsLog2);
  }
  // Prefetching needs the domain's runs of neighbour numbers: rows of the
  // stencil's block on a grid, single vertices from the adjacency list of a
  // cell mesh. Surfaces are not prefetched (not tried): measuring their
  // edges also reads the end points' positions and normals.
  static constexpr bool kPrefetches = DomainHooks<Domain>::kPrefetchesNeighborhood;
  std::vector<VertexState> state_;
  FrontQueue queue_;
  const typename ChainUnfolding<Domain>::EdgeMetric edgeMetric_;
  CandidatePath<Domain, Norm> path_;
  // The metric's sharedLookup where edges are measured in R^3 with the mean
  // of their end points' norms, for the batches (NeighborBatch::lookup);
  // null otherwise.
  const typename Norm::VertexParams* const lookup_;
  // Any-angle ancestors: where the domain's candidate paths are straight
  // segments measured from their two end points (grids, tetrahedral
  // meshes), and only with deferred measurement, whose records keep where
  // each distance was measured from.
  static constexpr bool kAnyAngle = !CandidatePath<Domain, Norm>::usesPlacedChain();
  // Offered only for norms that measure a straight segment exactly in every
  // direction (norms.hpp); on the others (lattice tables) the chain alone,
  // still with every distance's predecessor where it was measured from.
  const int anyAngle_ =
      SegmentMeasure && kAnyAngle && ExactInEveryDirection<Norm>::value ? options_.anyAngleAncestors : 0;
  const int segmentReach_ = reachOption(options_.segmentReach, false);
  const int sourceReach_ = reachOption(options_.sourceReach, true);
  Termination termination_ = Termination::Completed;
  std::uint64_t finalized_ = 0;
  std::uint64_t relaxed_ = 0;
  std::uint64_t measured_ = 0;
  std::uint64_t refused_ = 0;
  std::uint64_t peakBytes_ = 0;
  // The source lines' sources and per-vertex flags (offerSourceLines);
  // empty on the domains without them. Last, so that the other members
  // keep their places.
  struct SourceLine {
    VertexId vertex;
    double start;
  };
  std::vector<SourceLine> sourceLines_;
  std::vector<std::uint8_t> withoutSourceLine_;  // 1: the vertex was first reached with no source's line
};

}  // namespace detail
}  // namespace stvd
