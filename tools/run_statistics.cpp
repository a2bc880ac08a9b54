// The statistics file of the geodesic subcommands (see run_statistics.hpp).
#include "run_statistics.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "stvd/voxel_grid/voxel_grid_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd::tool {
namespace {

void writeParameters(std::ostringstream& j, const RunStatistics& run) {
  const PropagationChoice& o = *run.choice;
  const TensorInputOptions& tensor = *run.tensor;
  const imaging::TensorFileInfo& info = run.tensorInput->read.info;  // default for an FOD input
  j << "  \"parameters\": {\n";
  j << "    \"method\": " << jsonString(o.lanthier ? "lanthier" : o.method == Method::Dijkstra ? "dijkstra" : "stvd")
    << ",\n";
  if (o.lanthier) j << "    \"steiner_points\": " << o.steinerPoints << ",\n";
  j << "    \"k\": " << (o.lanthier ? std::string("null") : std::to_string(memoryDepthOf<VoxelGridDomain>(o)))
    << ",\n";
  if (!o.lanthier) {  // lanthier measures cells, not stencil edges or chains
    j << "    \"chain_measure\": \"" << chainMeasureName(o.chainMeasure) << "\",\n";
    j << "    \"stencil\": " << jsonString(o.stencil) << ",\n";
  }
  j << "    \"domain_connectivity\": " << static_cast<int>(o.connectivity) << ",\n";
  j << "    \"max_distance_mm\": " << jsonNumber(run.maxDistance) << ",\n";
  if (run.metricParameters.empty()) {
    j << "    \"tensor_kind\": " << jsonString(imaging::tensorKindName(tensor.metric.kind)) << ",\n";
    j << "    \"diffusion_metric\": " << jsonString(imaging::diffusionMetricName(tensor.metric.diffusionMetric))
      << ",\n";
    j << "    \"metric_formula\": "
      << jsonString(imaging::metricFormula(tensor.metric.kind, tensor.metric.diffusionMetric)) << ",\n";
    j << "    \"max_anisotropy\": " << jsonNumber(imaging::anisotropyCap(tensor.metric).value_or(NAN)) << ",\n";
    j << "    \"fa_threshold\": " << jsonNumber(tensor.metric.faThreshold.value_or(NAN)) << ",\n";
    j << "    \"tensor_input\": \"file\",\n";
    j << "    \"tensor_layout\": " << jsonString(imaging::tensorFileLayoutName(info.layout)) << ",\n";
    j << "    \"tensor_order\": " << jsonString(imaging::tensorOrderName(info.order)) << ",\n";
    j << "    \"tensor_order_stated\": " << (tensor.order ? "true" : "false") << ",\n";
    j << "    \"tensor_frame\": " << jsonString(imaging::tensorFrameName(info.frame)) << ",\n";
    j << "    \"tensor_frame_stated\": " << (info.frameWasStated ? "true" : "false") << ",\n";
  } else {  // another metric than tensors states its own
    for (const std::string& member : run.metricParameters) j << "    " << member << ",\n";
  }
  j << "    \"mask\": " << jsonString(tensor.maskPath) << ",\n";
  if (!run.labels.empty()) j << "    \"labels\": " << jsonString(run.labels) << ",\n";
  if (!run.targetLabels.empty()) j << "    \"target_labels\": " << jsonString(run.targetLabels) << ",\n";
  j << "    \"seed_labels\": " << jsonString(run.seedLabels);
  if (run.withUnreachableValue) j << ",\n    \"unreachable_value\": " << jsonNumber(run.unreachableValue);
  j << "\n  },\n";
}

}  // namespace

std::string commandLineText(int argc, char** argv) {
  std::string line = "stvd";
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const bool plain = !a.empty() && a.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                                         "0123456789-_./,=:+@%") == std::string::npos;
    line += ' ';
    if (plain) {
      line += a;
    } else {  // single quotes, each ' written as '\''
      line += '\'';
      for (char c : a) line += c == '\'' ? std::string("'\\''") : std::string(1, c);
      line += '\'';
    }
  }
  return line;
}

DistanceStatistics summariseDistances(const std::vector<double>& distance) {
  DistanceStatistics s;
  std::vector<double> finite;
  finite.reserve(distance.size());
  for (double d : distance)
    if (std::isfinite(d)) finite.push_back(d);
  s.reached = finite.size();
  if (finite.empty()) return s;
  s.maximum = *std::max_element(finite.begin(), finite.end());
  const std::size_t mid = finite.size() / 2;
  std::nth_element(finite.begin(), finite.begin() + mid, finite.end());
  s.median = finite[mid];
  if (finite.size() % 2 == 0) {
    const double below = *std::max_element(finite.begin(), finite.begin() + mid);
    s.median = 0.5 * (s.median + below);
  }
  return s;
}

std::string statisticsJson(const RunStatistics& run) {
  const GridGeometry& g = run.tensorInput->read.volume.geometry;
  const imaging::MetricVoxelCounts& counts = run.counts;
  std::ostringstream j;
  j << "{\n";
  j << "  \"command\": " << jsonString(run.command) << ",\n";
  j << "  \"stvd_version\": " << jsonString(STVD_VERSION_TEXT) << ",\n";
  j << "  \"command_line\": " << jsonString(run.commandLine) << ",\n";
  j << "  \"input\": " << jsonString(run.input) << ",\n";
  j << "  \"output\": " << jsonString(run.output) << ",\n";
  if (!run.outputs.empty()) {
    j << "  \"outputs\": {";
    for (std::size_t n = 0; n < run.outputs.size(); ++n)
      j << (n ? ", " : "") << jsonString(run.outputs[n].first) << ": " << jsonString(run.outputs[n].second);
    j << "},\n";
  }
  writeParameters(j, run);
  j << "  \"grid\": {\"size\": [" << g.size[0] << ", " << g.size[1] << ", " << g.size[2] << "], \"spacing_mm\": ["
    << jsonNumber(g.spacing[0]) << ", " << jsonNumber(g.spacing[1]) << ", " << jsonNumber(g.spacing[2])
    << "], \"origin_lps_mm\": [" << jsonNumber(g.origin[0]) << ", " << jsonNumber(g.origin[1]) << ", "
    << jsonNumber(g.origin[2]) << "]},\n";
  if (run.seeds) {
    const std::vector<Seed>& seeds = *run.seeds;
    j << "  \"seeds\": [";
    const std::size_t listed = std::min<std::size_t>(seeds.size(), 100);
    for (std::size_t s = 0; s < listed; ++s) {
      const Vec3d ras = lpsToRas(g.indexToPhysicalPoint(seeds[s].index.i, seeds[s].index.j, seeds[s].index.k));
      j << (s ? ", " : "") << "{\"voxel\": [" << seeds[s].index.i << ", " << seeds[s].index.j << ", "
        << seeds[s].index.k << "], \"ras_mm\": [" << jsonNumber(ras.x) << ", " << jsonNumber(ras.y) << ", "
        << jsonNumber(ras.z) << "]}";
    }
    j << "],\n";
    j << "  \"seed_count\": " << seeds.size() << ",\n";
    j << "  \"label_seeds_left_out\": " << run.labelSeedsLeftOut << ",\n";
  }
  j << "  \"voxels\": {\"total\": " << counts.total << ", \"domain\": " << counts.domain
    << ", \"masked\": " << counts.masked << ", \"zero_tensor\": " << counts.zero
    << ", \"non_finite_tensor\": " << counts.nonFinite
    << ", \"no_positive_eigenvalue\": " << counts.noPositiveEigenvalue
    << ", \"below_fa_threshold\": " << counts.belowFaThreshold << ", \"repaired\": " << counts.repaired()
    << ", \"repaired_non_positive\": " << counts.repairedNonPositive
    << ", \"repaired_anisotropy\": " << counts.repairedAnisotropy << "},\n";
  if (run.result) {
    const PropagationResult& result = *run.result;
    const DistanceStatistics stats = summariseDistances(result.distance);
    j << "  \"propagation\": {\"vertices\": " << g.voxelCount() << ", \"domain_vertices\": " << counts.domain
      << ", \"finalized_vertices\": " << result.finalizedVertices << ", \"relaxed_edges\": " << result.relaxedEdges
      << ", \"measured_candidates\": " << result.measuredCandidates
      << ", \"refused_candidates\": " << result.refusedCandidates << ", \"termination\": " << jsonString(terminationName(result.termination))
      << ", \"peak_state_bytes\": " << result.peakStateBytes << "},\n";
    j << "  \"distance_mm\": {\"reached\": " << stats.reached << ", \"min\": " << (stats.reached ? "0" : "null")
      << ", \"median\": " << (stats.reached ? jsonNumber(stats.median) : "null")
      << ", \"max\": " << (stats.reached ? jsonNumber(stats.maximum) : "null") << "},\n";
  }
  for (const std::string& member : run.extraMembers) j << "  " << member << ",\n";
  j << "  \"warnings\": [";
  for (std::size_t w = 0; w < inputWarnings().size(); ++w) j << (w ? ", " : "") << jsonString(inputWarnings()[w]);
  j << "],\n";
  j << "  \"seconds\": {";
  for (std::size_t n = 0; n < run.seconds.size(); ++n)
    j << (n ? ", " : "") << jsonString(run.seconds[n].first) << ": " << jsonNumber(run.seconds[n].second);
  j << "},\n";
  if (run.memory) j << "  \"memory\": " << memoryCheckJson(*run.memory) << ",\n";
  j << "  \"peak_memory_bytes\": " << peakMemoryBytes() << "\n";
  j << "}\n";
  return j.str();
}

}  // namespace stvd::tool
