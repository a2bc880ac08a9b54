// `stvd connectivity`: geodesic distance and a geodesic connectivity index
// between every pair of labelled regions, one multi-source propagation per
// region, the regions spread over threads.
#include <algorithm>
#include <functional>
#include <chrono>
#include <cmath>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "command_line.hpp"
#include "command_options.hpp"
#include "fod_input.hpp"
#include "geodesic_options.hpp"
#include "memory_check.hpp"
#include "option_help.hpp"
#include "report_request.hpp"
#include "tool_run_files.hpp"
#include "run_statistics.hpp"
#include "stvd/system/files/file_contents.hpp"
#include "stvd/system/files/output_transaction.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/voxel_grid/label_regions.hpp"
#include "stvd/imaging/fod_paths.hpp"
#include "stvd/system/parallel_tasks.hpp"
#include "stvd/voxel_grid/region_connectivity.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "stvd/front_end/memory_estimates.hpp"
#include "stvd/system/files/output_destination.hpp"
#include "stvd/itk/image_grid.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "stvd/front_end/region_connectivity_options.hpp"
#include "subcommands.hpp"

namespace stvd::tool {
namespace {

std::string connectivityHelp() {
  return "Usage: stvd connectivity INPUT --labels LABELS -o TABLE.tsv [options]\n"
         "\n"
         "Geodesic distance and connectivity between every pair of labelled regions of LABELS (an\n"
         "image on the grid of INPUT; each distinct non-zero integer value is a region). For each\n"
         "region A the distance is propagated from all of A's voxels in the domain at once (as\n"
         "`stvd distance --seeds` does); for every other region B, d(A, B) is the smallest distance\n"
         "at a voxel of B, and the geodesic path from that voxel back to A is traced as `stvd path`\n"
         "does. The connectivity index of the pair is the geodesic connectivity measure of Astola,\n"
         "Florack and ter Haar Romeny (IPMI 2007): the Euclidean length of that path divided by its\n"
         "geodesic length, L_E / L_G. Under G = (D/MD)^-1 it is about 1 through isotropic tissue and\n"
         "grows when the path follows directions of high diffusivity. See docs/paths.md.\n"
         "\n"
         "Output: one row per ordered pair (A, B), A != B, with region_a, region_b, geodesic_mm,\n"
         "path_mm (Euclidean length of the path), straight_mm (between the path's end points),\n"
         "connectivity (path_mm / geodesic_mm), voxels_a, voxels_b; n/a where B is not reachable from\n"
         "A. d(A, B) and d(B, A) are computed separately and agree up to discretisation.\n"
         "\n"
         "Regions:\n" +
         optionHelp(kConnectivityCommand, {OptionGroup::Regions}) +
         "\n"
         "Propagation (as in stvd distance; lanthier gives no paths):\n" +
         optionHelp(kConnectivityCommand, {OptionGroup::Propagation}) + "\n" +
         tensorInputHelp(kConnectivityCommand) +
         "\n"
         "FOD file (fibre orientation distributions, docs/fod.md): with --fod-basis the input is an FOD\n"
         "  image and the metric its convexified norm F*, propagated by Dijkstra; the path of each pair\n"
         "  is the propagation's discrete path (voxel centres), not traced or refined.\n" +
         optionHelp(kConnectivityCommand, {OptionGroup::FodFile}) +
         "\n"
         "Output:\n" +
         optionHelp(kConnectivityCommand, {OptionGroup::Output}) +
         "\n"
         "Exit codes: 0 success; 1 internal error; 2 bad command line; 3 unreadable or unusable\n"
         "input (also labels on another grid or not integers); 4 fewer than two regions with voxels\n"
         "in the domain; 5 output cannot be written; 6 not enough memory for the run.\n";
}

struct ConnectivityOptions : PropagationChoice {
  std::string input;
  std::string labels;
  std::string output;
  std::string matrix;       // --matrix
  std::string matrixIndex;  // --matrix-index
  std::string statsPath;
  std::string reportPath;
  std::string reportSubject;  // --subject: the page's name
  TensorInputOptions tensor;
  imaging::FodInputOptions fod;  ///< given(): the input is an FOD image
  unsigned threads = 0;
  bool quiet = false;
};

ConnectivityOptions parseConnectivityOptions(int argc, char** argv) {
  const CommandLine line = readCommandLine(kConnectivityCommand, argc, argv, 2, connectivityHelp);
  const OptionValues& v = line.values;
  ConnectivityOptions o;
  static_cast<PropagationChoice&>(o) = propagationChoiceOf(v);
  o.input = line.input;
  o.labels = v.text("--labels").value_or("");
  o.output = v.text("--output").value_or("");
  o.matrix = v.text("--matrix").value_or("");
  o.matrixIndex = v.text("--matrix-index").value_or("");
  o.statsPath = v.text("--stats").value_or("");
  o.reportPath = v.text("--report").value_or("");
  o.reportSubject = v.text("--subject").value_or("");
  o.tensor = imaging::tensorInputOptionsOf(v);
  o.threads = regionThreadsOf(v);
  o.quiet = v.has("--quiet");
  if (o.input.empty()) usageError("no input file (see stvd connectivity --help)");
  if (o.labels.empty()) usageError("no regions: add --labels LABELS");
  if (o.output.empty()) usageError("no output file: add -o TABLE.tsv");
  checkPropagationChoice(o, /*lanthierAllowed=*/false);
  o.fod = imaging::fodInputOptionsOf(v);
  if (!o.fod.given()) return o;
  checkFodRunOptions(v, o.stencil);
  // The paths are Dijkstra's predecessor chains (docs/fod.md, "Paths and connectivity").
  if (v.has("--method") && o.method != Method::Dijkstra)
    usageError("--method " + *v.text("--method") +
               ": connectivity on FOD images runs Dijkstra; use --method dijkstra, its default on FOD images");
  o.method = Method::Dijkstra;
  return o;
}

std::string number(double x) { return std::isfinite(x) ? fixed(x, 4) : "n/a"; }

/// One square matrix as CSV: '#' header lines, then row a, column b.
std::string matrixCsv(const std::string& what, const std::vector<LabelRegion>& regions,
                      const RegionConnectivity& table, bool index) {
  const std::size_t n = regions.size();
  std::ostringstream csv;
  csv << "# stvd connectivity: " << what << " from the region of the row to the region of the column\n# labels: ";
  for (std::size_t a = 0; a < n; ++a) csv << (a ? "," : "") << regions[a].label;
  csv << "\n";
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = 0; b < n; ++b) {
      const RegionPair& r = table(a, b);
      csv << (b ? "," : "");
      // No value on the diagonal and for pairs not connected: nan, the
      // missing value of every connectivity output (docs/paths.md).
      const double value = index ? r.connectivity() : r.geodesic;
      if (a == b || !std::isfinite(r.geodesic) || !std::isfinite(value)) csv << "nan";
      else csv << fixed(value, index ? 6 : 4);
    }
    csv << "\n";
  }
  return csv.str();
}

}  // namespace

int runConnectivity(int argc, char** argv) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const ConnectivityOptions o = parseConnectivityOptions(argc, argv);
  RunFiles files;
  files.inputImage(o.fod.given() ? "FOD input" : "tensor input", o.input);
  files.inputImage("mask", o.tensor.maskPath);
  files.inputImage("label image", o.labels);
  files.outputFile("connectivity table", o.output);
  files.outputFile("distance matrix", o.matrix);
  files.outputFile("connectivity-index matrix", o.matrixIndex);
  files.outputFile("statistics file", o.statsPath);
  files.outputFile("QC report", o.reportPath);
  files.check();
  ReportRequest report;
  report.start(o.reportPath, o.reportSubject);
  // The input and its metric: the tensors' or an FOD image's (docs/fod.md).
  std::optional<TensorInput> tensorInput;
  std::optional<imaging::MetricFromTensors> built;
  std::optional<FodInput> fodInput;
  if (o.fod.given()) {
    fodInput.emplace(readFodInput(o.input, o.fod, o.tensor.maskPath));
  } else {
    tensorInput.emplace(readTensorInputNotingWarnings(o.input, o.tensor));
    built.emplace(imaging::buildCheckedMetric(o.input, *tensorInput, o.tensor));
  }
  const TensorInput& input = fodInput ? fodInput->grid : *tensorInput;
  const std::vector<std::uint8_t>& inDomain = fodInput ? fodInput->inDomain : built->inDomain;
  const imaging::MetricVoxelCounts counts = fodInput ? fodInput->counts : built->counts;
  const GridGeometry& g = input.read.volume.geometry;

  const imaging::LabelImage labels = imaging::readLabelImageOnGrid(o.labels, g, "the labels are", o.input);
  noteInputWarnings(o.labels, labels.warnings);
  imaging::requireSameGrid(labels.geometry, g, o.labels, "the labels are", o.input);
  std::size_t empty = 0;
  const std::vector<LabelRegion> regions =
      regionsInDomain(labelRegions(labels.labels, inDomain), o.labels, o.input, empty);

  // One propagation at a time on each thread, each with its own state and result.
  const unsigned threadCount = threadCountFor(o.threads, regions.size());
  const std::uint64_t metricBytes =
      fodInput ? sizeof(imaging::FodStencilNorm::VertexParams) * g.voxelCount() : std::uint64_t(0);
  const MemoryCheck memory = checkMemory(
      o.input, threadCount * propagationMemoryEstimate(g.voxelCount(), counts.domain) + metricBytes,
      std::to_string(threadCount) + (threadCount == 1 ? " propagation" : " propagations at once") + " on " +
          withThousands(counts.domain) + " domain voxels",
      !o.memoryCheck);
  const VoxelGridDomain domain(g, Stencil::byName(o.stencil), inDomain, o.connectivity);
  const std::size_t n = regions.size();
  std::vector<std::vector<VertexId>> regionVoxels;
  for (const LabelRegion& r : regions) regionVoxels.push_back(r.voxels);
  // Region a's row is written only by the thread that propagates from a,
  // so the table is the same for any number of threads.
  RegionConnectivity table;
  FodTable fodTable;
  if (fodInput) {
    fodTable = makeFodTable(*fodInput, o.fod.cost, o.threads);
    table = imaging::fodRegionConnectivity(domain, fodTable.metric, regionVoxels, propagationOptions(o), threadCount);
  } else {
    const RiemannianMetric metric(std::move(built->metric), &built->inDomain);
    table = regionConnectivity(domain, metric, regionVoxels, propagationOptions(o), threadCount);
  }

  std::ostringstream tsv;
  tsv << "region_a\tregion_b\tgeodesic_mm\tpath_mm\tstraight_mm\tconnectivity\tvoxels_a\tvoxels_b\n";
  for (std::size_t a = 0; a < n; ++a)
    for (std::size_t b = 0; b < n; ++b) {
      if (a == b) continue;
      const RegionPair& r = table(a, b);
      const double index = r.connectivity();
      tsv << regions[a].label << "\t" << regions[b].label << "\t" << number(r.geodesic) << "\t" << number(r.pathLength)
          << "\t" << number(r.straight) << "\t" << number(index) << "\t" << regions[a].voxels.size() << "\t"
          << regions[b].voxels.size() << "\n";
    }
  report.requireReady();  // nothing is written when the report could not be drawn
  RunStatistics run = volumeRunStatistics("connectivity", commandLineText(argc, argv), o, input, counts);
  run.labels = o.labels;
  run.memory = &memory;
  if (fodInput) {
    run.metricParameters = fodMetricParameters(*fodInput, o.fod, fodTable);
    run.extraMembers = {fodPrecomputationMember(*fodInput, fodTable)};
  }
  run.extraMembers.push_back("\"regions\": {\"count\": " + std::to_string(n) + ", \"left_out\": " +
                             std::to_string(empty) + ", \"threads\": " + std::to_string(threadCount) + "}");
  run.seconds = {{"total", std::chrono::duration<double>(Clock::now() - start).count()}};
  // The table, the matrices and the statistics appear together or not at all.
  std::vector<std::pair<std::string, std::string>> texts{{o.output, tsv.str()}};
  if (!o.matrix.empty()) texts.emplace_back(o.matrix, matrixCsv("geodesic distance (mm)", regions, table, false));
  if (!o.matrixIndex.empty())
    texts.emplace_back(o.matrixIndex, matrixCsv("connectivity index (path_mm / geodesic_mm)", regions, table, true));
  if (!o.statsPath.empty()) texts.emplace_back(o.statsPath, statisticsJson(run));
  files::OutputTransaction outputs;
  try {
    for (const auto& pathAndText : texts) {
      const std::string& text = pathAndText.second;  // a structured binding cannot be captured in C++17
      outputs.write(pathAndText.first, [&](const std::string& staging) { files::writeFileContents(staging, text); });
    }
    outputs.commit();
  } catch (const files::OutputError& e) {
    throw ToolError(kExitOutput, e.what());
  }
  if (!o.quiet)
    std::cout << (fodInput ? fodInputText(o.input, *fodInput, o.fod, fodTable) + ".\n" : std::string())
              << "Connectivity of " << n << " regions of " << o.labels
              << (empty ? " (" + std::to_string(empty) + " more without voxels in the domain left out)" : std::string())
              << ": " << n * (n - 1) << " ordered pairs, " << methodText(o, memoryDepthOf<VoxelGridDomain>(o))
              << " on the " << o.stencil << "-neighbour stencil, " << connectivityText(o.connectivity) << ", "
              << threadCount << (threadCount == 1 ? " thread" : " threads") << ". Took "
              << fixed(std::chrono::duration<double>(Clock::now() - start).count(), 2) << " s. Wrote " << o.output
              << (o.matrix.empty() ? "" : ", " + o.matrix) << (o.matrixIndex.empty() ? "" : ", " + o.matrixIndex)
              << "." << std::endl;
  if (report.requested()) {
    const ScratchFolder scratch;
    std::vector<std::string> arguments{"--stats", scratch.statisticsFile(o.statsPath, statisticsJson(run))};
    if (files::isStreamOutput(o.output)) {  // a table sent to a stream cannot be read back: a copy
      try {
        files::writeFileContents(scratch.file("connectivity.tsv"), tsv.str());
      } catch (const std::runtime_error& e) {
        throw ToolError(kExitOutput, e.what());
      }
      arguments.insert(arguments.end(), {"--table", scratch.file("connectivity.tsv")});
    }
    report.write(arguments, o.quiet);
  }
  return kExitOk;
}

}  // namespace stvd::tool
