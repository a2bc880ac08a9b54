// `stvd path`: geodesic paths from targets back to the seeds over a tensor
// volume, written as streamlines (.tck, .trk, .vtk) with a TSV summary.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>

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
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/imaging/fod_paths.hpp"
#include "stvd/errors.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/imaging/streamline_io.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "stvd/front_end/memory_estimates.hpp"
#include "stvd/system/files/output_destination.hpp"
#include "stvd/front_end/path_tracing_options.hpp"
#include "stvd/front_end/region_connectivity_options.hpp"
#include "stvd/itk/image_grid.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "subcommands.hpp"

namespace stvd::tool {
namespace {

using Clock = std::chrono::steady_clock;

std::string pathHelp() {
  return "Usage: stvd path INPUT --seed-... --target-... -o PATHS [options]\n"
         "\n"
         "Geodesic paths (tractography-like curves) from each target back to the nearest seed under\n"
         "the metric of a diffusion or metric tensor volume: the distance from the seeds is propagated\n"
         "as `stvd distance` does (same seeds, tensor and method options and defaults), and each path\n"
         "descends that distance field from its target along the characteristic direction -G^-1 grad u\n"
         "(Heun's method, fixed step), falling back to the propagation's predecessor chain where the\n"
         "gradient vanishes, points out of the image or reaches a voxel outside the domain. The traced\n"
         "curve is then refined into a discrete geodesic of the metric itself (its end points fixed,\n"
         "never through voxels outside the domain), which removes the distance field's errors from\n"
         "its position. Each path runs from its seed end (first point) to its target (last point).\n"
         "See docs/paths.md.\n"
         "\n"
         "Seeds (at least one; all seeds are sources at distance 0):\n" +
         optionHelp(kPathCommand, {OptionGroup::Seeds}) +
         "Targets (at least one; one path per target):\n" +
         optionHelp(kPathCommand, {OptionGroup::Targets}) +
         "\n"
         "Propagation (as in stvd distance; lanthier gives no paths):\n" +
         optionHelp(kPathCommand, {OptionGroup::Propagation}) + "\n" + tensorInputHelp(kPathCommand) +
         "\n"
         "FOD file (fibre orientation distributions, docs/fod.md): with --fod-basis the input is an FOD\n"
         "  image and the metric its convexified norm F*, propagated by Dijkstra; each path is the\n"
         "  propagation's discrete path (voxel centres), whose F*-length is its geodesic length: no\n"
         "  gradient descent or refinement (--step, --smooth, --no-refine are refused).\n" +
         optionHelp(kPathCommand, {OptionGroup::FodFile, OptionGroup::Regions}) +
         "\n"
         "Paths:\n" +
         optionHelp(kPathCommand, {OptionGroup::Paths}) +
         "\n"
         "Output:\n" +
         optionHelp(kPathCommand, {OptionGroup::Output}) +
         "\n"
         "Exit codes: 0 success; 1 internal error; 2 bad command line; 3 unreadable or unusable\n"
         "input; 4 nothing to compute (empty domain, a seed or target outside the image or domain, a\n"
         "target not reachable from the seeds); 5 output cannot be written; 6 not enough memory for\n"
         "the run. No output file is left behind on failure.\n";
}

struct PathOptions : SeedOptions, PropagationChoice {
  std::string input;
  std::string output;
  std::string tsvPath;
  std::string statsPath;
  std::string reportPath;
  std::string reportSubject;  // --subject: the page's name
  std::vector<std::array<int, 3>> targetVoxels;
  std::vector<std::array<double, 3>> targetPoints;
  std::string targetLabels;
  TensorInputOptions tensor;
  imaging::FodInputOptions fod;  ///< given(): the input is an FOD image
  unsigned threads = 0;          ///< of the FOD metric's table (0: one per core)
  PathTracingOptions tracing;
  bool discrete = false;
  bool quiet = false;
};

std::string replaceExtension(const std::string& path, const std::string& extension) {
  const std::size_t slash = path.find_last_of('/');
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return path + extension;
  return path.substr(0, dot) + extension;
}

PathOptions parsePathOptions(int argc, char** argv) {
  const CommandLine line = readCommandLine(kPathCommand, argc, argv, 2, pathHelp);
  const OptionValues& v = line.values;
  PathOptions o;
  static_cast<SeedOptions&>(o) = seedOptionsOf(v);
  static_cast<PropagationChoice&>(o) = propagationChoiceOf(v);
  o.input = line.input;
  o.output = v.text("--output").value_or("");
  o.tsvPath = v.text("--tsv").value_or("");
  o.statsPath = v.text("--stats").value_or("");
  o.reportPath = v.text("--report").value_or("");
  o.reportSubject = v.text("--subject").value_or("");
  o.targetVoxels = imaging::voxelsOf(v, "--target-voxel");
  o.targetPoints = imaging::pointsOf(v, "--target-point");
  o.targetLabels = v.text("--targets").value_or("");
  o.tensor = imaging::tensorInputOptionsOf(v);
  o.tracing = pathTracingOptionsOf(v);
  o.discrete = v.has("--discrete");
  o.quiet = v.has("--quiet");
  if (o.input.empty()) usageError("no input file (see stvd path --help)");
  if (o.output.empty()) usageError("no output file: add -o PATHS.tck, .trk or .vtk");
  if (!imaging::streamlineFormatOf(o.output))
    usageError(o.output + ": unsupported output format; use .tck, .trk or .vtk");
  if (o.tsvPath.empty()) o.tsvPath = replaceExtension(o.output, ".tsv");
  if (o.seedVoxels.empty() && o.seedPoints.empty() && o.seedLabels.empty())
    usageError(imaging::noSeedMessage(OptionNaming::Flags));
  if (o.targetVoxels.empty() && o.targetPoints.empty() && o.targetLabels.empty())
    usageError(imaging::noTargetMessage(OptionNaming::Flags));
  checkPropagationChoice(o, /*lanthierAllowed=*/false);
  o.fod = imaging::fodInputOptionsOf(v);
  o.threads = regionThreadsOf(v);
  if (!o.fod.given()) {
    if (v.has("--threads")) usageError("--threads applies to FOD images (--fod-basis)");
    return o;
  }
  checkFodRunOptions(v, o.stencil);
  // The paths are Dijkstra's predecessor chains, whose F*-length is the
  // distance reported (docs/fod.md, "Paths and connectivity").
  if (v.has("--method") && o.method != Method::Dijkstra)
    usageError("--method " + *v.text("--method") +
               ": paths on FOD images are Dijkstra's; use --method dijkstra, the default for FOD paths");
  o.method = Method::Dijkstra;
  for (const char* flag : {"--step", "--smooth", "--no-refine"})
    if (v.has(flag))
      usageError(std::string(flag) +
                 ": paths on FOD images are the propagation's discrete paths, whose F*-length is the reported "
                 "length; they are not traced or refined (docs/fod.md)");
  o.discrete = true;
  return o;
}

/// What the tensor and the FOD runs of `stvd path` hand to the part they
/// share: the grid and domain (the seeds' and labels' readers take a
/// tensor input's), the propagation, the path of a target, FA along the
/// paths (empty: none) and the statistics' metric sections.
struct PathRunMetric {
  const TensorInput* input = nullptr;
  const std::vector<std::uint8_t>* inDomain = nullptr;
  imaging::MetricVoxelCounts counts;
  std::uint64_t metricBytes = 0;  ///< memory of the metric beyond the tensor run's estimate
  std::function<void()> prepare;  ///< makes the metric once the seeds, targets and memory are checked (or none)
  std::function<PropagationResult(const VoxelGridDomain&, const std::vector<VertexId>&)> propagate;
  std::function<TracedPath(const VoxelGridDomain&, const PropagationResult&, VertexId)> trace;
  std::function<std::vector<float>()> fa;  ///< FA per voxel, or none
  /// The metric's sections of the statistics and the summary's first
  /// sentence (FOD runs; asked for once `prepare` has made their table).
  std::function<std::vector<std::string>()> metricParameters, extraMembers;
  std::function<std::string()> inputText;
};

using Target = imaging::PathTarget;

std::string tsvNumber(double x, int decimals) { return std::isfinite(x) ? fixed(x, decimals) : "n/a"; }

int runPaths(const PathOptions& o, int argc, char** argv, Clock::time_point start, ReportRequest& report,
             const PathRunMetric& m) {
  const TensorInput& input = *m.input;
  const GridGeometry& g = input.read.volume.geometry;
  const std::vector<std::uint8_t>& inDomain = *m.inDomain;
  std::size_t leftOut = 0;
  const std::vector<Seed> seeds = resolveSeeds(o.input, o, input, o.tensor.metric, inDomain, leftOut);
  SeedOptions targetGiven;
  targetGiven.seedVoxels = o.targetVoxels;
  targetGiven.seedPoints = o.targetPoints;
  targetGiven.seedPointsInLps = o.seedPointsInLps;
  std::size_t unused = 0;
  const std::vector<Seed> targetSeeds =
      resolveSeeds(o.input, targetGiven, input, o.tensor.metric, inDomain, unused, "target");

  // The propagation, FA per voxel and the paths.
  const MemoryCheck memory = checkMemory(
      o.input,
      propagationMemoryEstimate(g.voxelCount(), m.counts.domain) + 2 * sizeof(float) * g.voxelCount() + m.metricBytes,
      methodText(o, memoryDepthOf<VoxelGridDomain>(o)) + " on " + withThousands(m.counts.domain) + " domain voxels",
      !o.memoryCheck);
  const VoxelGridDomain domain(g, Stencil::byName(o.stencil), inDomain, o.connectivity);
  const std::vector<VertexId> sources = imaging::sourceVertices(domain, seeds);
  const Clock::time_point metricStart = Clock::now();
  if (m.prepare) m.prepare();
  const Clock::time_point propagationStart = Clock::now();
  const double metricSeconds = std::chrono::duration<double>(propagationStart - metricStart).count();
  const PropagationResult result = m.propagate(domain, sources);
  const double propagationSeconds = std::chrono::duration<double>(Clock::now() - propagationStart).count();

  std::vector<Target> targets;
  for (const Seed& t : targetSeeds) targets.push_back({domain.vertexAt(t.index.i, t.index.j, t.index.k), t.givenAs});
  if (!o.targetLabels.empty()) {
    const imaging::LabelImage labels =
        imaging::readLabelImageOnGrid(o.targetLabels, g, "the target labels are", o.input);
    noteInputWarnings(o.targetLabels, labels.warnings);
    const std::vector<Target> fromLabels =
        imaging::labelTargets(o.targetLabels, labels, o.input, g, inDomain, result.distance);
    targets.insert(targets.end(), fromLabels.begin(), fromLabels.end());
  }
  imaging::requireReachable(o.input, targets, result.distance);

  // FA of the diffusion tensors, for the values along the paths.
  const bool withFa = static_cast<bool>(m.fa);
  std::vector<float> fa;
  if (withFa) fa = m.fa();

  const Clock::time_point tracingStart = Clock::now();
  imaging::StreamlineSet set;
  set.geometry = g;
  set.lineValueNames = {"geodesic_mm", "euclidean_mm"};
  set.lineValues.resize(2);
  if (withFa) {
    set.lineValueNames.push_back("mean_fa");
    set.lineValues.emplace_back();
    set.pointValueNames = {"fa"};
    set.pointValues.resize(1);
  }
  std::ostringstream tsv;
  tsv << "path\ttarget\ttarget_i\ttarget_j\ttarget_k\ttarget_x_ras_mm\ttarget_y_ras_mm\ttarget_z_ras_mm\tseed_i\tseed_j"
         "\tseed_k\tgeodesic_mm\teuclidean_mm\tstraight_mm\tmetric_length_mm\tmean_fa\tpoints\tgradient_steps"
         "\tdiscrete_points\tfallbacks\trefine_iterations\n";
  std::ostringstream summary;
  for (std::size_t n = 0; n < targets.size(); ++n) {
    const Target& t = targets[n];
    const TracedPath path = m.trace(domain, result, t.vertex);
    double meanFa = std::numeric_limits<double>::quiet_NaN();
    if (withFa) {
      const PathSamples faAlong = sampleAlongPath(domain, fa, path.points);
      meanFa = faAlong.lengthWeightedMean;
      set.pointValues[0].push_back(faAlong.values);
      set.lineValues[2].push_back(static_cast<float>(meanFa));
    }
    set.lines.push_back(path.points);
    set.lineValues[0].push_back(static_cast<float>(path.geodesicLength));
    set.lineValues[1].push_back(static_cast<float>(path.euclideanLength));

    const VoxelIndex ti = domain.indexOf(t.vertex), si = domain.indexOf(path.discrete.front());
    const Vec3d ras = lpsToRas(domain.physicalPoint(t.vertex));
    const double straight = norm(domain.physicalPoint(t.vertex) - domain.physicalPoint(path.discrete.front()));
    std::string fallbacks;
    for (int f = 0; f < kPathFallbackKinds; ++f)
      if (path.fallbacks[f])
        fallbacks += (fallbacks.empty() ? "" : ",") + std::string(pathFallbackName(static_cast<PathFallback>(f))) +
                     "=" + std::to_string(path.fallbacks[f]);
    tsv << n + 1 << "\t" << t.name << "\t" << ti.i << "\t" << ti.j << "\t" << ti.k << "\t" << fixed(ras.x, 3) << "\t"
        << fixed(ras.y, 3) << "\t" << fixed(ras.z, 3) << "\t" << si.i << "\t" << si.j << "\t" << si.k << "\t"
        << fixed(path.geodesicLength, 4) << "\t" << fixed(path.euclideanLength, 4) << "\t" << fixed(straight, 4) << "\t"
        << tsvNumber(path.metricLength, 4) << "\t" << tsvNumber(meanFa, 4) << "\t" << path.points.size() << "\t"
        << path.gradientSteps << "\t" << path.discretePoints << "\t" << (fallbacks.empty() ? "none" : fallbacks)
        << "\t" << path.refinement.iterations << "\n";
    summary << "Path " << n + 1 << " from " << t.name << " to seed voxel " << voxelText(si) << ": geodesic "
            << fixed(path.geodesicLength, 1) << " mm, length " << fixed(path.euclideanLength, 1) << " mm (straight "
            << fixed(straight, 1) << " mm)";
    if (withFa) summary << ", mean FA " << tsvNumber(meanFa, 3);
    summary << ", " << path.points.size() << " points";
    if (path.fallbackCount()) summary << ", fallbacks " << fallbacks;
    summary << ".\n";
  }
  const double tracingSeconds = std::chrono::duration<double>(Clock::now() - tracingStart).count();

  report.requireReady();  // nothing is written when the report could not be drawn
  RunStatistics run = volumeRunStatistics("path", commandLineText(argc, argv), o, input, m.counts);
  if (m.metricParameters) run.metricParameters = m.metricParameters();
  run.outputs = {{"paths", o.output}, {"paths_table", o.tsvPath}};
  run.seedLabels = o.seedLabels;
  run.targetLabels = o.targetLabels;
  run.seeds = &seeds;
  run.labelSeedsLeftOut = leftOut;
  run.result = &result;
  run.memory = &memory;
  if (m.extraMembers) run.extraMembers = m.extraMembers();
  run.extraMembers.push_back("\"path_count\": " + std::to_string(targets.size()));
  if (m.prepare) run.seconds.emplace_back("metric", metricSeconds);
  run.seconds.insert(run.seconds.end(), {{"propagate", propagationSeconds},
                                         {"paths", tracingSeconds},
                                         {"total", std::chrono::duration<double>(Clock::now() - start).count()}});
  // The paths, their table and the statistics appear together or not at all.
  files::OutputTransaction outputs;
  const std::string table = tsv.str();
  try {
    imaging::writeStreamlines(outputs, o.output, set);
    outputs.write(o.tsvPath, [&](const std::string& staging) { files::writeFileContents(staging, table); });
    if (!o.statsPath.empty()) {
      const std::string json = statisticsJson(run);
      outputs.write(o.statsPath, [&](const std::string& staging) { files::writeFileContents(staging, json); });
    }
    outputs.commit();
  } catch (const std::runtime_error& e) {  // files::OutputError, imaging::ImageIoError
    throw ToolError(kExitOutput, e.what());
  }
  if (!o.quiet) {
    std::cout << (m.inputText ? m.inputText() : std::string()) << summary.str();
    std::cout << "Method: " << methodText(o, memoryDepthOf<VoxelGridDomain>(o)) << " on the " << o.stencil
              << "-neighbour stencil, " << connectivityText(o.connectivity) << "; " << seeds.size()
              << (seeds.size() == 1 ? " seed voxel" : " seed voxels") << ". Took "
              << fixed(std::chrono::duration<double>(Clock::now() - start).count(), 2) << " s (propagation "
              << fixed(propagationSeconds, 2) << ", paths " << fixed(tracingSeconds, 3) << "). Wrote " << o.output
              << " and " << o.tsvPath << (o.statsPath.empty() ? "" : " and " + o.statsPath) << "." << std::endl;
  }
  if (report.requested()) {
    // The report shows the paths over the distance map, which `stvd path`
    // does not write: it goes to a scratch folder, with the statistics when
    // they were not asked for.
    const ScratchFolder scratch;
    const std::string statsPath = scratch.statisticsFile(o.statsPath, statisticsJson(run));
    std::vector<float> values(result.distance.size());
    for (std::size_t v = 0; v < values.size(); ++v)
      values[v] = std::isfinite(result.distance[v]) ? static_cast<float>(result.distance[v])
                                                    : std::numeric_limits<float>::quiet_NaN();
    std::vector<std::string> arguments{"--stats", statsPath, "--distance", scratch.file("distance.nii")};
    try {
      imaging::writeScalarImage(scratch.file("distance.nii"), g, values);
      // Paths or a table sent to a stream (a FIFO, /dev/stdout) cannot be
      // read back: the report gets copies.
      if (files::isStreamOutput(o.output) || files::isStreamOutput(o.tsvPath)) {
        const std::string paths = scratch.file("paths" + std::filesystem::path(o.output).extension().string());
        imaging::writeStreamlines(paths, set);
        files::writeFileContents(scratch.file("paths.tsv"), table);
        arguments.insert(arguments.end(), {"--paths", paths, "--paths-table", scratch.file("paths.tsv")});
      }
    } catch (const std::runtime_error& e) {
      throw ToolError(kExitOutput, e.what());
    }
    report.write(arguments, o.quiet);
  }
  return kExitOk;
}

}  // namespace

int runPath(int argc, char** argv) {
  const Clock::time_point start = Clock::now();
  const PathOptions o = parsePathOptions(argc, argv);
  RunFiles files;
  files.inputImage(o.fod.given() ? "FOD input" : "tensor input", o.input);
  files.inputImage("mask", o.tensor.maskPath);
  files.inputImage("seed labels", o.seedLabels);
  files.inputImage("target labels", o.targetLabels);
  files.outputFile("paths file", o.output);
  files.outputFile("path table", o.tsvPath);
  files.outputFile("statistics file", o.statsPath);
  files.outputFile("QC report", o.reportPath);
  files.check();
  ReportRequest report;
  report.start(o.reportPath, o.reportSubject);

  PathRunMetric m;
  if (o.fod.given()) {
    // `stvd path FOD --fod-basis NAME`: Dijkstra under F* (docs/fod.md).
    const FodInput in = readFodInput(o.input, o.fod, o.tensor.maskPath);
    // The table is made once the seeds, targets and memory are checked.
    FodTable table;
    m.input = &in.grid;
    m.inDomain = &in.inDomain;
    m.counts = in.counts;
    m.metricBytes = sizeof(imaging::FodStencilNorm::VertexParams) * in.fod.geometry.voxelCount();
    m.prepare = [&] { table = makeFodTable(in, o.fod.cost, o.threads); };
    m.propagate = [&](const VoxelGridDomain& domain, const std::vector<VertexId>& sources) {
      return propagate(domain, table.metric, sources, propagationOptions(o));
    };
    m.trace = [&](const VoxelGridDomain& domain, const PropagationResult& result, VertexId target) {
      return imaging::fodGeodesicPath(domain, table.metric, result, target);
    };
    m.metricParameters = [&] { return fodMetricParameters(in, o.fod, table); };
    m.extraMembers = [&] { return std::vector<std::string>{fodPrecomputationMember(in, table)}; };
    m.inputText = [&] { return fodInputText(o.input, in, o.fod, table) + ".\n"; };
    return runPaths(o, argc, argv, start, report, m);
  }
  const TensorInput input = readTensorInputNotingWarnings(o.input, o.tensor);
  imaging::MetricFromTensors built = imaging::buildCheckedMetric(o.input, input, o.tensor);
  if (built.counts.domain == 0)
    throw ToolError(kExitDomain, o.input + ": the domain is empty: no voxel has a usable tensor");
  const RiemannianMetric metric(std::move(built.metric), &built.inDomain);
  m.input = &input;
  m.inDomain = &built.inDomain;
  m.counts = built.counts;
  m.propagate = [&](const VoxelGridDomain& domain, const std::vector<VertexId>& sources) {
    return propagate(domain, metric, sources, propagationOptions(o));
  };
  m.trace = [&](const VoxelGridDomain& domain, const PropagationResult& result, VertexId target) {
    return o.discrete ? discreteGeodesicPath(domain, result, target)
                      : traceGeodesicPath(domain, metric, result, target, o.tracing);
  };
  // FA of the diffusion tensors, for the values along the paths.
  if (o.tensor.metric.kind == imaging::TensorKind::Diffusion)
    m.fa = [&] { return imaging::fractionalAnisotropyMap(input.read.volume.tensors, built.inDomain); };
  return runPaths(o, argc, argv, start, report, m);
}

}  // namespace stvd::tool
