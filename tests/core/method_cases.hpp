// Propagation options per method for the specifications: withMethod() for
// one run, and the methods that method-independent specifications (masks,
// stop conditions) run under, as GoogleTest value parameters.
#pragma once

#include <gtest/gtest.h>

#include <string>

#include "stvd/propagation.hpp"

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

  PropagationOptions options() const { return withMethod(method, k); }
};

inline const MethodCase kMethodCases[] = {{"Dijkstra", Method::Dijkstra, 1},
                                          {"StvdK4", Method::ShortTermVectorDijkstra, 4},
                                          {"StvdK8", Method::ShortTermVectorDijkstra, 8},
                                          {"StvdK16", Method::ShortTermVectorDijkstra, 16}};

inline std::string methodCaseName(const ::testing::TestParamInfo<MethodCase>& info) {
  return info.param.name;
}

}  // namespace stvd::test
