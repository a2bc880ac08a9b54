// Lanthier's method over any cell structure (private to the library):
// Dijkstra over the implicit graph of the Steiner points, whose neighbours a
// cell layout (voxel_grid/voxel_grid_steiner_cells.hpp,
// cell_mesh/tetrahedral_steiner_cells.hpp, surface/surface_steiner_cells.hpp)
// generates cell by cell, and the checks every domain's entry point makes.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/detail/front_queue.hpp"
#include "stvd/propagation/detail/progress_hook.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/system/large_array.hpp"

namespace stvd::detail {

/// The reports of the setup before a Steiner-point propagation: the cell
/// layout and the propagation's state (on the brain with M = 8, 29 million
/// points), an operation of its own for the interrupter, "Steiner cells"
/// (start, 0 %, at least every progressInterval, 100 %, end). The progress
/// callback hears the same reports as the run's first ones, with no vertex
/// final yet (fraction 0), so that a host that only has the callback (the
/// tool's bar, the Python package) can cancel here too.
class LanthierSetupRelay final : public Interrupter {
 public:
  LanthierSetupRelay(const LanthierOptions& options, VertexId domainVertexCount)
      : options_(options), domainVertices_(domainVertexCount) {}
  /// This relay, or nullptr when nobody listens.
  Interrupter* target() { return options_.interrupter || options_.progress ? this : nullptr; }
  void start(const char* name) override {
    if (options_.interrupter) options_.interrupter->start(name);
  }
  void end() override {
    if (options_.interrupter) options_.interrupter->end();
  }
  bool wasInterrupted(int percent) override {
    bool stop = false;
    if (options_.progress) {
      PropagationProgress p;
      p.domainVertices = domainVertices_;
      stop = !options_.progress(p);
    }
    if (options_.interrupter && options_.interrupter->wasInterrupted(percent)) stop = true;
    return stop;
  }

 private:
  const LanthierOptions& options_;
  VertexId domainVertices_;
};

/// Progress through the setup: `done` counts its steps (voxels or faces of
/// a pass over the domain, entries of an array filled) out of the total the
/// scope was given. Throws Cancelled when asked to stop.
struct SetupProgress {
  InterruptScope& scope;
  std::uint64_t done = 0;
  /// After one step of a loop: a bit test, the clock every 1024 steps.
  void step() { scope.step(++done); }
  /// After `n` steps at once.
  void add(std::uint64_t n) {
    done += n;
    scope.check(done);
  }
};

/// `count` copies of `value`, filled a piece at a time with the setup's
/// reports between pieces (2 x 29 million entries on the brain with M = 8
/// take longer than a report interval); huge pages as makeLargeArray.
template <class T>
std::vector<T> filledWithProgress(std::size_t count, const T& value, SetupProgress& setup, bool hugePages) {
  constexpr std::size_t kPiece = std::size_t{1} << 18;
  std::vector<T> array;
  array.reserve(count);
  if (hugePages) adviseHugePages(array.data(), count * sizeof(T));
  while (array.size() < count) {
    const std::size_t n = std::min(kPiece, count - array.size());
    array.resize(array.size() + n, value);
    setup.add(n);
  }
  return array;
}

/// The boundary points of one cell, seen from one of them (`self`).
/// Positions are relative to a point of the cell (float is enough: a cell
/// is small). Point l has id idBase + idOffset[l].
struct SteinerCellView {
  const VertexId* corners;
  int cornerCount;
  int pointCount;
  SteinerPointId idBase;
  const SteinerPointId* idOffset;
  const Vec3f* position;
  Vec3f self;
};

/// Dijkstra over the implicit Steiner graph of `cells`.
template <class Cells, class Norm>
class LanthierDijkstra {
 public:
  /// Allocates the state of cells.pointCount() points: 2 pointCount() steps
  /// of `setup`.
  LanthierDijkstra(Cells& cells, const MetricField<Norm>& metric, VertexId vertexCount,
                  VertexId domainVertexCount, const LanthierOptions& options, SetupProgress& setup)
      : cells_(cells),
        metric_(metric),
        options_(options),
        vertexCount_(vertexCount),
        domainVertexCount_(domainVertexCount),
        distance_(filledWithProgress(cells.pointCount(), kUnreachable, setup, false)),
        slots_(filledWithProgress(cells.pointCount(), FrontQueue::kUnseen, setup, true)),
        queue_(slots_.data(), 0),
        length_(cells.maxCellPoints()),
        corner_(cells.maxCellCorners()) {}

  LanthierResult run(const std::vector<VertexId>& sources) {
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

    LanthierResult result;
    // Progress counts original vertices: they are finalised interleaved with
    // the Steiner points in distance order, and unlike the points they all
    // lie in the domain. Reports are paced in time (ProgressHook).
    ProgressHook hook(options_.progress, options_.interrupter, options_.progressInterval,
                      "Steiner-point propagation");
    PropagationProgress progress;
    progress.domainVertices = domainVertexCount_;
    std::uint64_t finalizedPoints = 0;
    if (hook.active() && !hook.report(progress)) result.termination = Termination::Cancelled;
    while (result.termination != Termination::Cancelled && !queue_.empty()) {
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
      if (hook.due(finalizedPoints)) {
        peakBytes_ = std::max(peakBytes_, stateBytes());
        progress.finalizedVertices = result.finalizedVertices;
        progress.frontDistance = distance_[u];
        progress.fraction =
            double(result.finalizedVertices) / double(std::max<std::uint64_t>(progress.domainVertices, 1));
        if (!hook.report(progress)) {
          result.termination = Termination::Cancelled;
          break;
        }
      }
      relax(u);
    }
    peakBytes_ = std::max(peakBytes_, stateBytes());
    if (hook.active() && result.termination != Termination::Cancelled) {
      progress.finalizedVertices = result.finalizedVertices;
      progress.fraction = 1.0;
      hook.report(progress);
    }
    // A cancelled run holds no distances (PropagationOptions::progress).
    const bool cancelled = result.termination == Termination::Cancelled;

    result.relaxedEdges = relaxed_;
    result.peakStateBytes = peakBytes_ + isTarget.capacity();
    result.graphPoints = cells_.pointCount();
    result.distance.assign(vertexCount_, kUnreachable);
    result.predecessor.assign(vertexCount_, kNoVertex);
    result.hasPredecessors = false;
    for (VertexId w = 0; w < (cancelled ? 0 : vertexCount_); ++w) {
      const SteinerPointId p = cells_.pointOfVertex(w);  // kNoVertex: a voxel outside the domain
      if (p != kNoVertex && queue_.isFinal(p)) result.distance[w] = distance_[p];
    }
    if (options_.keepPointDistances) {
      // Only final points carry a distance.
      for (std::uint64_t p = 0; p < distance_.size(); ++p)
        if (cancelled || !queue_.isFinal(static_cast<SteinerPointId>(p))) distance_[p] = kUnreachable;
      result.pointDistance = std::move(distance_);
    }
    return result;
  }

 private:
  std::uint64_t stateBytes() const {
    return distance_.capacity() * sizeof(double) + slots_.capacity() * sizeof(std::uint32_t) +
           queue_.capacityBytes() + length_.capacity() * sizeof(float) +
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
  const LanthierOptions& options_;
  VertexId vertexCount_, domainVertexCount_;
  std::vector<double> distance_;
  std::vector<std::uint32_t> slots_;  // the queue's, filled under the setup's reports
  FrontQueue queue_;
  std::vector<float> length_;
  std::vector<const typename Norm::VertexParams*> corner_;
  std::uint64_t relaxed_ = 0;
  std::uint64_t peakBytes_ = 0;
};

/// What a run cancelled during its setup returns: as a run cancelled while
/// it propagates, no distances (every vertex kUnreachable, no predecessor)
/// and nothing finalised.
inline LanthierResult cancelledLanthierResult(VertexId vertexCount, std::uint64_t graphPoints) {
  LanthierResult result;
  result.termination = Termination::Cancelled;
  result.distance.assign(vertexCount, kUnreachable);
  result.predecessor.assign(vertexCount, kNoVertex);
  result.hasPredecessors = false;
  result.graphPoints = graphPoints;
  return result;
}

/// Sets up the cells (Cells(cellArguments..., SetupProgress&), taking
/// `cellSteps` steps) and the propagation's state for their points (at
/// most `pointCountBound`) under the setup's reports (LanthierSetupRelay),
/// then runs Lanthier's Dijkstra from `sources`. A stop asked for during
/// the setup returns cancelledLanthierResult.
template <class Cells, class Norm, class... CellArguments>
LanthierResult setUpAndRunLanthier(const MetricField<Norm>& metric, VertexId vertexCount, VertexId domainVertexCount,
                                   const std::vector<VertexId>& sources, const LanthierOptions& options,
                                   std::uint64_t cellSteps, std::uint64_t pointCountBound,
                                   CellArguments&&... cellArguments) {
  std::optional<Cells> cells;
  std::optional<LanthierDijkstra<Cells, Norm>> dijkstra;
  LanthierSetupRelay relay(options, domainVertexCount);
  try {
    InterruptScope scope(relay.target(), "Steiner cells", cellSteps + 2 * pointCountBound,
                         options.progressInterval);
    SetupProgress setup{scope};
    cells.emplace(std::forward<CellArguments>(cellArguments)..., setup);
    scope.setTotal(cellSteps + 2 * cells->pointCount());
    dijkstra.emplace(*cells, metric, vertexCount, domainVertexCount, options, setup);
    scope.finish();
  } catch (const Cancelled&) {
    return cancelledLanthierResult(vertexCount, cells ? cells->pointCount() : 0);
  }
  return dijkstra->run(sources);
}

template <class DomainLike, class Norm>
void validate(const DomainLike& domain, VertexId vertexCount, const MetricField<Norm>& metric,
              const std::vector<VertexId>& sources, const LanthierOptions& options) {
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

}  // namespace stvd::detail
