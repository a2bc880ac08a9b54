// `stvd connectivity`: geodesic distance and a geodesic connectivity index
// between every pair of labelled regions, one multi-source propagation per
// region, the regions spread over threads.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <sstream>

#include "command_line.hpp"
#include "geodesic_options.hpp"
#include "report_request.hpp"
#include "run_statistics.hpp"
#include "stvd/geodesic_path.hpp"
#include "stvd/itk/atomic_output.hpp"
#include "stvd/itk/image_io_error.hpp"
#include "stvd/itk/scalar_image.hpp"
#include "stvd/label_regions.hpp"
#include "stvd/region_connectivity.hpp"
#include "stvd/stencil.hpp"
#include "subcommands.hpp"

namespace stvd::tool {
namespace {

const char* kConnectivityHelp =
    "Usage: stvd connectivity INPUT --labels LABELS -o TABLE.tsv [options]\n"
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
    "  --labels LABELS         the region image (required).\n"
    "  -o, --output FILE       the table (required); written atomically.\n"
    "  --threads N             regions propagated in parallel (default: the number of cores);\n"
    "                          the table does not depend on N.\n"
    "  --method, --k, --chain-measure, --stencil   as in stvd distance (defaults stvd, 8,\n"
    "                          largest, 26).\n"
    "  --stats FILE.json       parameters, counts and seconds as JSON (as stvd distance writes).\n"
    "  --report FILE.html      a self-contained QC page: the regions over FA, the matrices as heat\n"
    "                          maps, the statistics and the warnings (Python 3 and matplotlib;\n"
    "                          docs/report.md).\n"
    "  -q, --quiet             no summary on stdout.\n"
    "\n"
    "%TENSOR%"
    "\n"
    "Exit codes: 0 success; 1 internal error; 2 bad command line; 3 unreadable or unusable\n"
    "input (also labels on another grid or not integers); 4 fewer than two regions with voxels\n"
    "in the domain; 5 output cannot be written.\n";

struct ConnectivityOptions : PropagationChoice {
  std::string input;
  std::string labels;
  std::string output;
  std::string statsPath;
  std::string reportPath;
  TensorInputOptions tensor;
  unsigned threads = 0;
  bool quiet = false;
};

ConnectivityOptions parseConnectivityOptions(int argc, char** argv) {
  ConnectivityOptions o;
  ArgumentReader args(argc, argv, 2);
  while (!args.done()) {
    const std::string a = args.take();
    if (takeInputOrHelp(a, args, o.input, kConnectivityHelp, true)) continue;
    if (a == "-o" || a == "--output") {
      o.output = args.value(a);
    } else if (a == "--labels") {
      o.labels = args.value(a);
    } else if (a == "--stats") {
      o.statsPath = args.value(a);
    } else if (a == "--report") {
      o.reportPath = args.value(a);
    } else if (a == "--threads") {
      const int n = parseInteger(a, args.value(a));
      if (n < 1 || n > 1024) usageError("--threads must be between 1 and 1024");
      o.threads = static_cast<unsigned>(n);
    } else if (a == "-q" || a == "--quiet") {
      args.noValue(a);
      o.quiet = true;
    } else if (parsePropagationOption(a, args, o)) {
    } else if (!parseTensorInputOption(a, args, o.tensor)) {
      usageError("unknown option '" + a + "' (see stvd connectivity --help)");
    }
  }
  if (o.input.empty()) usageError("no input file (see stvd connectivity --help)");
  if (o.labels.empty()) usageError("no regions: add --labels LABELS");
  if (o.output.empty()) usageError("no output file: add -o TABLE.tsv");
  checkPropagationChoice(o, /*lanthierAllowed=*/false);
  return o;
}

std::string number(double x) { return std::isfinite(x) ? fixed(x, 4) : "n/a"; }

}  // namespace

int runConnectivity(int argc, char** argv) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const ConnectivityOptions o = parseConnectivityOptions(argc, argv);
  try {
    imaging::checkOutputPath(o.output);
    if (!o.statsPath.empty()) imaging::checkOutputPath(o.statsPath);
  } catch (const imaging::ImageIoError& e) {
    throw ToolError(kExitOutput, e.what());
  }
  ReportRequest report;
  report.start(o.reportPath);
  const TensorInput input = readTensorInput(o.input, o.tensor);
  const GridGeometry& g = input.read.volume.geometry;
  imaging::MetricFromTensors built = imaging::buildMetric(input.read.volume.tensors, input.mask, o.tensor.metric);

  imaging::ScalarImage labels;
  try {
    labels = imaging::readScalarImage(o.labels);
  } catch (const imaging::ImageIoError& e) {
    throw ToolError(kExitInput, e.what());
  }
  imaging::requireSameGrid(labels.geometry, g, o.labels, "the labels are", o.input);
  std::size_t empty = 0;
  const std::vector<LabelRegion> regions =
      regionsInDomain(labelRegions(o.labels, labels.values, built.inDomain), o.labels, o.input, empty);

  const VoxelGridDomain domain(g, Stencil::byName(o.stencil), built.inDomain);
  const RiemannianMetric metric(std::move(built.metric), &built.inDomain);
  const std::size_t n = regions.size();
  std::vector<std::vector<VertexId>> regionVoxels;
  for (const LabelRegion& r : regions) regionVoxels.push_back(r.voxels);
  const RegionConnectivity table = regionConnectivity(domain, metric, regionVoxels, propagationOptions(o), o.threads);
  const unsigned threadCount = table.threads;

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
  RunStatistics run;
  run.command = "connectivity";
  run.commandLine = commandLineText(argc, argv);
  run.input = o.input;
  run.output = o.output;
  run.choice = &o;
  run.tensor = &o.tensor;
  run.tensorInput = &input;
  run.counts = built.counts;
  run.labels = o.labels;
  run.extraMembers = {"\"regions\": {\"count\": " + std::to_string(n) + ", \"left_out\": " + std::to_string(empty) +
                      ", \"threads\": " + std::to_string(threadCount) + "}"};
  run.seconds = {{"total", std::chrono::duration<double>(Clock::now() - start).count()}};
  try {
    writeTextAtomically(o.output, tsv.str());
    if (!o.statsPath.empty()) writeTextAtomically(o.statsPath, statisticsJson(run));
  } catch (const imaging::ImageIoError& e) {
    throw ToolError(kExitOutput, e.what());
  }
  if (!o.quiet)
    std::cout << "Connectivity of " << n << " regions of " << o.labels
              << (empty ? " (" + std::to_string(empty) + " more without voxels in the domain left out)" : std::string())
              << ": " << n * (n - 1) << " ordered pairs, " << methodText(o) << " on the " << o.stencil
              << "-neighbour stencil, " << threadCount << (threadCount == 1 ? " thread" : " threads") << ". Took "
              << fixed(std::chrono::duration<double>(Clock::now() - start).count(), 2) << " s. Wrote " << o.output
              << "." << std::endl;
  if (report.requested()) {
    ScratchFolder scratch;
    const std::string statsPath = o.statsPath.empty() ? scratch.file("run.json") : o.statsPath;
    try {
      if (o.statsPath.empty()) writeTextAtomically(statsPath, statisticsJson(run));
    } catch (const imaging::ImageIoError& e) {
      throw ToolError(kExitOutput, e.what());
    }
    report.write({"--stats", statsPath}, o.quiet);
  }
  return kExitOk;
}

}  // namespace stvd::tool
