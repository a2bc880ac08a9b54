// The definition of stvd::propagate. Include it in one translation unit to
// instantiate the propagation for a domain or a norm of your own; the
// built-in domains and norms are compiled in the library.
#pragma once

#include <cmath>
#include <initializer_list>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "stvd/propagation/detail/relaxation.hpp"
#include "stvd/propagation/propagation.hpp"

namespace stvd {

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
  if (!options.sourceDistances.empty() && options.sourceDistances.size() != sources.size())
    throw std::invalid_argument(std::to_string(options.sourceDistances.size()) + " source distances for " +
                                std::to_string(sources.size()) + " sources");
  for (const double d : options.sourceDistances)
    if (!(d >= 0.0) || !std::isfinite(d))
      throw std::invalid_argument("a source distance must be finite and not negative");
  for (const VertexId t : options.targets)
    if (!domain.contains(t))
      throw std::invalid_argument("target vertex " + std::to_string(t) +
                                  " lies outside the domain");
  const int k = memoryDepth<Domain>(options);
  if (options.method == Method::ShortTermVectorDijkstra && (k < 1 || k > kMaxMemoryDepth))
    throw std::invalid_argument("STVD memory depth k = " + std::to_string(k) + " is outside 1.." +
                                std::to_string(kMaxMemoryDepth));
  if (std::isnan(options.maxDistance))
    throw std::invalid_argument("maximum distance is NaN");
  if (options.anyAngleAncestors < 0 || options.anyAngleAncestors > kMaxAnyAngleAncestors)
    throw std::invalid_argument("any-angle ancestors " + std::to_string(options.anyAngleAncestors) +
                                " is outside 0.." + std::to_string(kMaxAnyAngleAncestors));
  for (const std::optional<int>& reach : {options.segmentReach, options.sourceReach})
    if (reach && *reach < 1)
      throw std::invalid_argument("segment reach " + std::to_string(*reach) + " is below 1");
  // ChainMeasure::Segment on a domain that measures along paths defers its
  // measurements, with a record of its own per vertex.
  if (options.method == Method::ShortTermVectorDijkstra && options.chainMeasure == ChainMeasure::Segment &&
      k > 1 && measuresPathsOn<Domain, Norm>(domain))
    return detail::Propagation<Domain, Norm, true>(domain, metric, options).run(sources);
  return detail::Propagation<Domain, Norm, false>(domain, metric, options).run(sources);
}

}  // namespace stvd
