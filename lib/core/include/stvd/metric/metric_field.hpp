// A metric sampled at the vertices of a domain.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "stvd/metric/norms.hpp"
#include "stvd/types.hpp"

namespace stvd {

/// One norm per vertex, in the vertex numbering of the domain it is used
/// with. Edges are measured with Norm::edgeParams of their two end points.
template <class Norm>
class MetricField {
 public:
  using VertexParams = typename Norm::VertexParams;

  MetricField() = default;
  /// Takes the per-vertex parameters. When `inDomain` is not null, only
  /// vertices with a non-zero entry are validated (the others are never
  /// visited). Throws std::invalid_argument naming the first vertex whose
  /// parameters do not define a norm.
  explicit MetricField(std::vector<VertexParams> params,
                       const std::vector<std::uint8_t>* inDomain = nullptr)
      : params_(std::move(params)) {
    for (std::size_t v = 0; v < params_.size(); ++v) {
      if (inDomain && (*inDomain)[v] == 0) continue;
      const std::string why = Norm::invalidReason(params_[v]);
      if (!why.empty())
        throw std::invalid_argument("metric at vertex " + std::to_string(v) + ": " + why);
    }
    if constexpr (TableLookup<Norm>::value) {
      lookupShared_ = !params_.empty();
      for (std::size_t v = 1; v < params_.size() && lookupShared_; ++v)
        lookupShared_ = Norm::sameLookup(params_[0], params_[v]);
    }
  }
  /// The same norm at every vertex.
  static MetricField constant(std::size_t vertexCount, const VertexParams& p) {
    return MetricField(std::vector<VertexParams>(vertexCount, p));
  }

  std::size_t size() const { return params_.size(); }
  const VertexParams& operator[](std::size_t v) const { return params_[v]; }
  const std::vector<VertexParams>& params() const { return params_; }

  /// For a norm with a table lookup (TableLookup, norms.hpp) whose field
  /// holds the lookup's parameters alike at every vertex (a lattice table's
  /// index transform, the grid's): a vertex's parameters, from which any
  /// vector is looked up for every vertex. Null otherwise, and for every
  /// other norm. Found once, when the field is made.
  const VertexParams* sharedLookup() const { return lookupShared_ ? &params_[0] : nullptr; }

 private:
  std::vector<VertexParams> params_;
  bool lookupShared_ = false;
};

using RiemannianMetric = MetricField<RiemannianNorm>;
using RandersMetric = MetricField<RandersNorm>;

}  // namespace stvd
