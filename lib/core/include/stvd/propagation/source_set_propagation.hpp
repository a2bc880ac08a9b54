// Many independent propagations at once: one per source set (a region of a
// label image, a seed set), spread over threads. This is how stvd uses
// more than one core: a single propagation is sequential (its front is a
// priority queue), but the propagations of different source sets share
// only the read-only domain and metric.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "stvd/propagation/propagation.hpp"
#include "stvd/system/parallel_tasks.hpp"

namespace stvd {

/// Propagates from each of `sourceSets` separately (every set is one
/// multi-source propagation, as propagate() with that set) on `threads`
/// threads (0: one per core) and hands each result to
/// consume(setIndex, PropagationResult&&) as soon as it is done. consume is
/// called from the worker threads, concurrently for different sets, so it
/// must only touch what belongs to its set (or lock); once it returns, the
/// result's memory is freed, so at most `threads` results are alive at once.
///
/// Each result is exactly the one propagate() gives for that set alone,
/// whatever the number of threads (the propagation is deterministic and
/// the sets share nothing writable). options.progress, if set, is called
/// from several threads. Throws what propagate() throws for the
/// lowest-numbered set that fails (after the running propagations finish).
template <class Domain, class Norm, class Consume>
void propagateEachSourceSet(const Domain& domain, const MetricField<Norm>& metric,
                            const std::vector<std::vector<VertexId>>& sourceSets,
                            const PropagationOptions& options, unsigned threads,
                            Consume&& consume) {
  forEachTaskInParallel(sourceSets.size(), threads, [&](std::size_t set) {
    consume(set, propagate(domain, metric, sourceSets[set], options));
  });
}

}  // namespace stvd
