// The run of regionConnectivity (region_connectivity.hpp) for any metric
// that propagate() is compiled for, with the paths traced by a function of
// the caller's: the core instantiates it for the Riemannian metric with
// traceGeodesicPath, the imaging adapter for the FOD norm with the discrete
// path (imaging/fod_paths.hpp), so that both have one threading, one
// progress report and one cancellation.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <vector>

#include "stvd/propagation/propagation.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/system/parallel_tasks.hpp"
#include "stvd/voxel_grid/label_regions.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/voxel_grid/region_connectivity.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {
namespace detail {

/// The caller's interrupter as the propagations and paths of one run hear
/// it: once anything asked to stop (the interrupter, a propagation's
/// progress callback, a task), every report answers stop, so that the
/// propagations and paths running on other threads end at their next
/// report instead of running to their end.
class RegionRunInterrupter final : public Interrupter {
 public:
  explicit RegionRunInterrupter(Interrupter* caller) : caller_(caller) {}
  void start(const char* name) override {
    if (caller_) caller_->start(name);
  }
  void end() override {
    if (caller_) caller_->end();
  }
  bool wasInterrupted(int percent) override {
    if (caller_ && caller_->wasInterrupted(percent)) stop();
    return stopped();
  }
  void stop() { stopped_.store(true, std::memory_order_relaxed); }
  bool stopped() const { return stopped_.load(std::memory_order_relaxed); }

 private:
  Interrupter* caller_;
  std::atomic<bool> stopped_{false};
};

}  // namespace detail

/// regionConnectivity's run under `metric`: `tracePath(result, vertex,
/// tracing)` gives the path from a vertex back to the sources of `result`
/// (its geodesicLength, euclideanLength and points), `tracing` carrying
/// the run's interrupter when the caller gave one.
template <class Metric, class TracePath>
RegionConnectivity regionConnectivityWith(const VoxelGridDomain& domain, const Metric& metric,
                                          const std::vector<std::vector<VertexId>>& regionVoxels,
                                          const PropagationOptions& options, unsigned threads,
                                          const PathTracingOptions& tracing, const TracePath& tracePath) {
  RegionConnectivity out;
  const std::size_t n = regionVoxels.size();
  out.regionCount = n;
  out.pairs.resize(n * n);
  out.threads = threadCountFor(threads, n);

  // The run's own reports ("region connectivity": the share of the
  // ordered pairs measured, a region's propagation counting as one more
  // pair) come from every thread, one at a time; the propagations and
  // paths report as operations of their own in between.
  detail::RegionRunInterrupter interrupter(options.interrupter);
  const bool listening = options.interrupter != nullptr;
  PropagationOptions propagation = options;
  PathTracingOptions paths = tracing;
  if (listening) {
    propagation.interrupter = &interrupter;
    if (!paths.interrupter) {
      paths.interrupter = &interrupter;
      paths.progressInterval = options.progressInterval;
    }
  }
  std::mutex reportMutex;
  std::uint64_t measured = 0;
  InterruptScope progress(listening ? &interrupter : nullptr, "region connectivity", std::uint64_t(n) * n,
                          options.progressInterval);
  auto measuredOne = [&] {
    std::lock_guard<std::mutex> lock(reportMutex);
    progress.check(++measured);
  };
  auto stopIfAsked = [&] {
    if (interrupter.stopped()) throw Cancelled("region connectivity was interrupted");
  };

  forEachTaskInParallel(n, out.threads, [&](std::size_t a) {
    stopIfAsked();
    const PropagationResult result = propagate(domain, metric, regionVoxels[a], propagation);
    if (result.termination == Termination::Cancelled) {
      interrupter.stop();  // also when the progress callback asked: the other threads stop too
      stopIfAsked();
    }
    measuredOne();
    for (std::size_t b = 0; b < n; ++b) {
      if (b == a) continue;
      stopIfAsked();
      const VertexId nearest = nearestReached(result.distance, regionVoxels[b]);
      if (nearest != kNoVertex) {
        const TracedPath path = tracePath(result, nearest, paths);
        RegionPair& r = out.pairs[a * n + b];
        r.geodesic = path.geodesicLength;
        r.pathLength = path.euclideanLength;
        r.straight = norm(path.points.back() - path.points.front());
      }
      measuredOne();
    }
  });
  progress.finish();
  return out;
}

}  // namespace stvd
