// Propagation options per method for the specifications: withMethod() for
// one run, and the methods that method-independent specifications (masks,
// stop conditions) run under, as GoogleTest value parameters.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "stvd/propagation/propagation.hpp"

namespace stvd::test {

inline PropagationOptions withMethod(Method method, int k = kDefaultMemoryDepth,
                                     ChainMeasure measure = ChainMeasure::ProjectionWeighted) {
  PropagationOptions o;
  o.method = method;
  o.k = k;
  o.chainMeasure = measure;
  return o;
}

struct MethodCase {
  const char* name;
  Method method;
  int k;
  ChainMeasure measure;

  PropagationOptions options() const { return withMethod(method, k, measure); }
};

/// Dijkstra, STVD with the default segment measure at three depths, and
/// the two chain rules at k = 8.
inline const MethodCase kMethodCases[] = {
    {"Dijkstra", Method::Dijkstra, 1, kDefaultChainMeasure},
    {"StvdK4", Method::ShortTermVectorDijkstra, 4, ChainMeasure::Segment},
    {"StvdK8", Method::ShortTermVectorDijkstra, 8, ChainMeasure::Segment},
    {"StvdK16", Method::ShortTermVectorDijkstra, 16, ChainMeasure::Segment},
    {"StvdK8Paper", Method::ShortTermVectorDijkstra, 8, ChainMeasure::ProjectionWeighted},
    {"StvdK8Largest", Method::ShortTermVectorDijkstra, 8, ChainMeasure::LargestEdgeNorm}};

inline std::string methodCaseName(const ::testing::TestParamInfo<MethodCase>& info) {
  return info.param.name;
}

}  // namespace stvd::test
