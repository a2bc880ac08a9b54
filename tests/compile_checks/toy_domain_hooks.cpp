// Compiled by tests/compile_checks/CMakeLists.txt: a domain of one's own is
// propagated over only once it says how (DomainHooks). Without
// STVD_WITH_HOOKS this file must not compile, and the compiler must name
// DomainHooks; with it, it must.
#include <vector>

#include "stvd/propagation/candidate_path.hpp"
#include "stvd/propagation/chain_unfolding.hpp"
#include "stvd/propagation/propagation_definition.hpp"

namespace {

/// Two vertices one millimetre apart, joined by one edge.
struct TwoPoints {
  stvd::VertexId vertexCount() const { return 2; }
  stvd::VertexId domainVertexCount() const { return 2; }
  bool contains(stvd::VertexId v) const { return v < 2; }
  stvd::Vec3d physicalPoint(stvd::VertexId v) const { return {double(v), 0.0, 0.0}; }
  stvd::Vec3f displacement(stvd::VertexId from, stvd::VertexId to) const {
    return {float(to) - float(from), 0.f, 0.f};
  }
  template <class F>
  void forEachNeighbor(stvd::VertexId v, F&& f) const {
    f(1 - v, displacement(v, 1 - v));
  }
};

}  // namespace

#ifdef STVD_WITH_HOOKS
namespace stvd {
template <>
struct DomainHooks<TwoPoints> {
  template <class Norm>
  using CandidatePath = UncheckedCandidatePath<TwoPoints, Norm>;
  using ChainUnfolding = VolumeChainUnfolding<TwoPoints>;
  static constexpr int kDefaultMemoryDepth = stvd::kDefaultMemoryDepth;
  static constexpr bool kPrefetchesNeighborhood = false;
  static constexpr bool kChainContinuesAlongStep = false;
};
}  // namespace stvd
#endif

template stvd::PropagationResult stvd::propagate(const TwoPoints&, const stvd::RiemannianMetric&,
                                                 const std::vector<stvd::VertexId>&,
                                                 const stvd::PropagationOptions&);
