// The error-versus-time tables that stvd_steiner_table (grids) and
// stvd_surface_steiner_table (surfaces) print: one Markdown row per method,
// Lanthier's Steiner points next to Dijkstra and STVD.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "relative_error.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"

namespace stvd::bench {

/// Wall seconds of one call of f.
template <class F>
double timedSeconds(F&& f) {
  const auto start = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

inline void printSteinerTableHeader() {
  std::printf("| method | mean rel. error | max rel. error | seconds | relaxed edges | ns / relaxed edge | "
              "graph points | peak state MiB |\n");
  std::printf("|---|---|---|---|---|---|---|---|\n");
}

/// `points`: the vertices of the graph the method ran on (Steiner points
/// included for Lanthier).
inline void printSteinerTableRow(const std::string& label, const test::RelativeErrors& e, const PropagationResult& r,
                                 std::uint64_t points, double seconds) {
  std::printf("| %s | %.3f %% | %.1f %% | %.3f | %.3g | %.1f | %.3g | %.2f |\n", label.c_str(), 100.0 * e.mean(),
              100.0 * e.max(), seconds, double(r.relaxedEdges), 1e9 * seconds / double(r.relaxedEdges),
              double(points), double(r.peakStateBytes) / (1024.0 * 1024.0));
  std::fflush(stdout);
}

/// One row per Lanthier run with M = 1, 2, 4, ... <= maxSteiner Steiner
/// points per edge: row(label, result, graph points, seconds).
template <class Domain, class Metric, class Row>
void printLanthierRows(const Domain& domain, const Metric& metric, const std::vector<VertexId>& sources,
                       int maxSteiner, Row&& row) {
  for (int m = 1; m <= maxSteiner; m *= 2) {
    LanthierOptions o;
    o.steinerPoints = m;
    LanthierResult sr;
    const double s = timedSeconds([&] { sr = lanthierPropagate(domain, metric, sources, o); });
    row("Lanthier M = " + std::to_string(m), sr, sr.graphPoints, s);
  }
}

}  // namespace stvd::bench
