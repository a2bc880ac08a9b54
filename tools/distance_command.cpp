// `stvd distance`: the anisotropic geodesic distance from seeds over a
// tensor volume, written as a float32 image on the input's grid.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <ctime>
#include <functional>
#include <cmath>
#include <filesystem>
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
#include "stvd/system/files/termination_signals.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/imaging/symmetric_eigen.hpp"
#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "stvd/system/files/output_destination.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/imaging/fod_input_options.hpp"
#include "stvd/imaging/fod_metric.hpp"
#include "stvd/imaging/fod_segment_norm.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/itk/fod_volume_io.hpp"
#include "stvd/itk/image_grid.hpp"
#include "stvd/errors.hpp"
#include "stvd/front_end/region_connectivity_options.hpp"
#include "stvd/system/parallel_tasks.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "subcommands.hpp"
#include "surface_distance_command.hpp"
#include "tet_mesh_commands.hpp"

#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"
#include "stvd/front_end/memory_estimates.hpp"

#ifdef STVD_WITH_VDB_OUTPUT
#include "stvd/vdb/distance_grid.hpp"
#endif

namespace stvd::tool {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

/// The help of the command on tensor volumes.
std::string volumeHelp() {
  return "Usage: stvd distance INPUT -o OUTPUT [options]\n"
         "       stvd distance MESH.obj|off|ply|stl -o OUT.ply|vtk|csv --seed-vertex N|--seed-point X,Y,Z\n"
         "       stvd distance MESH.node -o OUT.vtk|vtu|csv|nii.gz --seed-vertex N|--seed-point X,Y,Z\n"
         "\n"
         "Anisotropic geodesic distance (millimetres) from seed voxels over a diffusion or metric\n"
         "tensor volume. The output format follows the extension: .nii, .nii.gz, .nrrd, .nhdr, .mif or\n"
         ".mif.gz give a float32 image on exactly the input's grid (same size, spacing, origin and\n"
         "direction cosines), in which voxels not reached (outside the domain, disconnected from the seeds, or\n"
         "beyond --max-distance) hold the unreachable value, " +
         optionDefaultText(toolOption("--unreachable-value"), kDistanceCommand) +
         " unless --unreachable-value says\n"
         "otherwise; .vdb gives an OpenVDB FloatGrid named \"distance\" whose transform places the\n"
         "voxels in RAS millimetres and in which voxels not reached are inactive. All coordinates\n"
         "are millimetres; distances are measured in physical space (spacing and direction cosines\n"
         "applied). Polygon surfaces (.obj, .off, .ply, .stl) and TetGen tetrahedral meshes (.node,\n"
         ".ele) take the options of their own sections below.\n"
         "\n"
         "Seeds (at least one; all given seeds are sources at distance 0):\n" +
         optionHelp(kDistanceCommand, {OptionGroup::Seeds}) +
         "\n"
         "Propagation:\n" +
         optionHelp(kDistanceCommand, {OptionGroup::Propagation}) + "\n" + tensorInputHelp(kDistanceCommand) +
         "\n"
         "FOD file (fibre orientation distributions, docs/fod.md): with --fod-basis the input is an FOD\n"
         "  image, X Y Z N spherical-harmonic coefficients (.mif, .mif.gz, .mih, .nii, .nii.gz); --mask\n"
         "  and the seed options as for tensors.\n" +
         optionHelp(kDistanceCommand, {OptionGroup::FodFile, OptionGroup::Regions}) +
         "\n"
         "Output:\n" +
         optionHelp(kDistanceCommand, {OptionGroup::Output}) +
         "\n"
         "Unless --quiet, a one-paragraph summary goes to stdout, and a progress bar to stderr when\n"
         "stderr is a terminal and the propagation takes longer than a second.\n"
         "\n"
         "Exit codes: 0 success; 1 internal error; 2 bad command line; 3 unreadable or unusable\n"
         "input (format, layout, geometry of mask or labels); 4 nothing to compute (empty domain, a\n"
         "seed outside the image or the domain); 5 output cannot be written; 6 not enough memory for\n"
         "the run. On failure one line on stderr names the file and the problem, and no output file\n"
         "is left behind.\n";
}

/// The whole help: volumes, then surfaces and tetrahedral meshes in
/// sections of their own.
std::string distanceHelp() {
  return volumeHelp() +
         "\n=== Polygon surfaces: stvd distance MESH.obj|off|ply|stl -o OUT.ply|vtk|csv (docs/surfaces.md) ===\n\n" +
         surfaceOptionsHelp() +
         "\n=== Tetrahedral meshes: stvd distance MESH.node -o OUT.vtk|vtu|csv|nii.gz (docs/tet_meshes.md) ===\n\n" +
         tetMeshOptionsHelp();
}

struct DistanceOptions : SeedOptions, PropagationChoice {
  std::string input;
  std::string output;
  double maxDistance = std::numeric_limits<double>::infinity();
  TensorInputOptions tensor;
  imaging::FodInputOptions fod;  ///< given(): the input is an FOD image
  unsigned threads = 0;          ///< of the FOD metric's table (0: one per core)
  float unreachableValue = static_cast<float>(kDefaultUnreachableValue);
  std::string statsPath;
  std::string reportPath;
  std::string reportSubject;  // --subject: the page's name
  bool quiet = false;
};

bool isVdbPath(const std::string& path) {
  return path.size() > 4 && (path.compare(path.size() - 4, 4, ".vdb") == 0 || path.compare(path.size() - 4, 4, ".VDB") == 0);
}

DistanceOptions parseDistanceOptions(int argc, char** argv) {
  const CommandLine line = readCommandLine(kDistanceCommand, argc, argv, 2, distanceHelp);
  const OptionValues& v = line.values;
  DistanceOptions o;
  static_cast<SeedOptions&>(o) = seedOptionsOf(v);
  static_cast<PropagationChoice&>(o) = propagationChoiceOf(v);
  o.input = line.input;
  o.output = v.text("--output").value_or("");
  o.maxDistance = v.number("--max-distance").value_or(o.maxDistance);
  o.tensor = imaging::tensorInputOptionsOf(v);
  o.unreachableValue = static_cast<float>(v.number("--unreachable-value").value_or(o.unreachableValue));
  o.statsPath = v.text("--stats").value_or("");
  o.reportPath = v.text("--report").value_or("");
  o.reportSubject = v.text("--subject").value_or("");
  o.quiet = v.has("--quiet");
  if (o.input.empty()) usageError("no input file (see stvd distance --help)");
  if (o.output.empty()) usageError("no output file: add -o OUTPUT");
  if (isVdbPath(o.output)) {
#ifndef STVD_WITH_VDB_OUTPUT
    usageError(o.output + ": this stvd was built without OpenVDB; use .nii, .nii.gz, .nrrd, .nhdr, .mif or .mif.gz");
#endif
  } else if (!imaging::hasImageExtension(o.output)) {
    usageError(o.output + ": unsupported output format; use .nii, .nii.gz, .nrrd, .nhdr, .mif, .mif.gz or .vdb");
  }
  checkImageOutputSpelling(o.output);
  if (o.seedVoxels.empty() && o.seedPoints.empty() && o.seedLabels.empty())
    usageError(imaging::noSeedMessage(OptionNaming::Flags));
  checkPropagationChoice(o, /*lanthierAllowed=*/true);
  o.fod = imaging::fodInputOptionsOf(v);
  o.threads = regionThreadsOf(v);
  if (!o.fod.given()) {
    if (v.has("--threads")) usageError("--threads applies to FOD images (--fod-basis)");
    return o;
  }
  // STVD is the default here as for tensors: its segment-norm table costs
  // 1.2 times Dijkstra's 26-direction table for errors 2.6 times smaller
  // (docs/fod.md, "The tool").
  checkFodRunOptions(v, o.stencil);
  return o;
}

/// Shows a bar on stderr when it is a terminal and the run has lasted more
/// than a second; erases it at the end.
class ProgressBar {
 public:
  explicit ProgressBar(bool enabled, const char* label = "propagating")
      : enabled_(enabled && ::isatty(STDERR_FILENO)), label_(label), start_(Clock::now()) {}
  ~ProgressBar() { finish(); }
  void update(double fraction) {
    if (!enabled_ || secondsSince(start_) < 1.0) return;
    const int percent = static_cast<int>(fraction * 100.0);
    if (percent == lastPercent_) return;  // redraw only when the bar moves
    lastPercent_ = percent;
    const int width = 40;
    const int filled = static_cast<int>(std::clamp(fraction, 0.0, 1.0) * width);
    // One write, which the interruption line never splits (writeProgressText).
    std::ostringstream line;
    line << "\r" << label_ << " [" << std::string(filled, '#') << std::string(width - filled, ' ') << "] " << percent
         << "% " << fixed(secondsSince(start_), 1) << " s";
    std::cerr << std::flush;
    files::writeProgressText(line.str());
    shown_ = true;
  }
  void finish() {
    if (shown_) files::writeProgressText("\r" + std::string(72, ' ') + "\r");
    shown_ = false;
  }

 private:
  bool enabled_;
  const char* label_;
  bool shown_ = false;
  int lastPercent_ = -1;
  Clock::time_point start_;
};

/// The FOD table's reports on a bar of their own (the tool never cancels
/// from its bar; Ctrl-C ends the run through the signal thread).
class TableBar final : public Interrupter {
 public:
  explicit TableBar(bool enabled) : bar_(enabled, "FOD table") {}
  bool wasInterrupted(int percent) override {
    if (percent >= 0) bar_.update(percent / 100.0);
    return false;
  }
  void end() override { bar_.finish(); }

 private:
  ProgressBar bar_;
};


/// The run of `o`'s method on `metric` from `sources`, drawn on a progress
/// bar: Lanthier's method when asked for, STVD or Dijkstra otherwise.
/// `LanthierCells`: whether Lanthier's method is compiled for `Metric`'s norm
/// (not for the FOD's 26-direction table, which only Dijkstra uses).
template <bool LanthierCells = true, class Metric>
PropagationResult propagateForTool(const DistanceOptions& o, const VoxelGridDomain& domain, const Metric& metric,
                                   const std::vector<VertexId>& sources) {
  PropagationOptions options = propagationOptions(o);
  options.maxDistance = o.maxDistance;
  ProgressBar bar(!o.quiet);
  options.progress = [&bar](const PropagationProgress& p) {
    bar.update(p.domainVertices ? double(p.finalizedVertices) / double(p.domainVertices) : 0.0);
    return true;
  };
  PropagationResult result;
  if constexpr (LanthierCells) {
    if (o.lanthier) {
      LanthierOptions steiner;
      steiner.steinerPoints = o.steinerPoints;
      steiner.maxDistance = o.maxDistance;
      steiner.progress = options.progress;
      try {
        result = lanthierPropagate(domain, metric, sources, steiner);
      } catch (const std::invalid_argument& e) {  // too large a graph
        throw ToolError(kExitUsage, o.input + ": --method lanthier: " + e.what());
      }
      bar.finish();
      return result;
    }
  }
  result = propagate(domain, metric, sources, options);
  bar.finish();
  return result;
}

struct Timings {
  double read = 0, metric = 0, propagate = 0, write = 0, total = 0;
};

/// Checks the run's files before the work (RunFiles): `inputRole` names
/// the input in messages; paths not given are left out.
void checkRunFiles(const DistanceOptions& o, const std::string& inputRole) {
  RunFiles files;
  files.inputImage(inputRole, o.input);
  files.inputImage("mask", o.tensor.maskPath);
  files.inputImage("seed labels", o.seedLabels);
  if (isVdbPath(o.output))
    files.outputFile("distance map", o.output);
  else
    files.outputImage("distance map", o.output);
  files.outputFile("statistics file", o.statsPath);
  files.outputFile("QC report", o.reportPath);
  files.check();
}

/// The map's values: distances, the unreachable value where none.
std::vector<float> distanceValues(const DistanceOptions& o, const PropagationResult& result) {
  std::vector<float> values(result.distance.size());
  for (std::size_t v = 0; v < values.size(); ++v)
    values[v] = std::isfinite(result.distance[v]) ? static_cast<float>(result.distance[v]) : o.unreachableValue;
  return values;
}

/// Writes the map and the statistics file together or not at all (one
/// output transaction); `statistics` makes the run's record once the write
/// time is known. `phase`: when writing began.
RunStatistics commitDistanceOutputs(const DistanceOptions& o, const GridGeometry& g, const PropagationResult& result,
                                    const std::vector<float>& values, Timings& t, Clock::time_point start,
                                    Clock::time_point phase,
                                    const std::function<RunStatistics(const Timings&)>& statistics) {
  files::OutputTransaction outputs;
  RunStatistics run;
  try {
    if (isVdbPath(o.output)) {
#ifdef STVD_WITH_VDB_OUTPUT
      vdb::DistanceGridOptions grid;
      grid.background = std::isfinite(o.unreachableValue) ? o.unreachableValue : -1.f;
      vdb::writeDistanceGrid(outputs, o.output, g, result.distance, grid);
#else
      (void)result;  // refused when parsing the options
#endif
    } else {
      imaging::writeScalarImage(outputs, o.output, g, values);
    }
    t.write = secondsSince(phase);
    t.total = secondsSince(start);
    run = statistics(t);
    if (!o.statsPath.empty()) {
      const std::string json = statisticsJson(run);
      outputs.write(o.statsPath, [&](const std::string& staging) { files::writeFileContents(staging, json); });
    }
    outputs.commit();
  } catch (const files::OutputError& e) {
    throw ToolError(kExitOutput, e.what());
  }
  return run;
}

/// The statistics file's record of the run.
RunStatistics runStatistics(const DistanceOptions& o, const std::string& commandLine, const TensorInput& input,
                            const imaging::MetricVoxelCounts& counts, const std::vector<Seed>& seeds,
                            std::size_t labelSeedsLeftOut, const PropagationResult& result,
                            const MemoryCheck& memory, const Timings& t) {
  RunStatistics run = volumeRunStatistics("distance", commandLine, o, input, counts);
  run.maxDistance = o.maxDistance;
  run.seedLabels = o.seedLabels;
  run.withUnreachableValue = true;
  run.unreachableValue = o.unreachableValue;
  run.seeds = &seeds;
  run.labelSeedsLeftOut = labelSeedsLeftOut;
  run.result = &result;
  run.memory = &memory;
  run.seconds = {{"read", t.read}, {"metric", t.metric}, {"propagate", t.propagate}, {"write", t.write},
                 {"total", t.total}};
  return run;
}

std::string summaryParagraph(const DistanceOptions& o, const TensorInput& input,
                             const imaging::MetricVoxelCounts& counts, const std::vector<Seed>& seeds,
                             std::size_t labelSeedsLeftOut, const PropagationResult& result,
                             const DistanceStatistics& stats, const Timings& t) {
  const GridGeometry& g = input.read.volume.geometry;
  const imaging::TensorFileInfo& info = input.read.info;
  std::ostringstream s;
  s << "Read " << o.input << " (" << imaging::tensorFileLayoutName(info.layout) << ", components "
    << imaging::tensorOrderComponents(info.order) << " in the " << imaging::tensorFrameName(info.frame)
    << " frame" << (info.frameWasStated ? "" : " by default") << "): " << g.size[0] << " x " << g.size[1]
    << " x " << g.size[2] << " voxels of " << fixed(g.spacing[0], 2) << " x " << fixed(g.spacing[1], 2) << " x "
    << fixed(g.spacing[2], 2) << " mm, orientation " << orientationCode(g);
  const double oblique = imaging::obliquityDegrees(g);
  if (oblique >= 0.05) s << ", oblique by " << fixed(oblique, 1) << " degrees";
  s << ". ";
  if (o.tensor.metric.kind == imaging::TensorKind::Diffusion)
    s << "Metric " << imaging::metricFormula(o.tensor.metric.kind, o.tensor.metric.diffusionMetric)
      << " from the diffusion tensors";
  else
    s << "The file's tensors are the metric";
  if (const auto cap = imaging::anisotropyCap(o.tensor.metric))
    s << ", eigenvalue ratio capped at " << fixed(*cap, 0);
  else
    s << ", taken as given (no eigenvalue ratio cap)";
  s << "; " << withThousands(counts.domain) << " voxels in the domain";
  if (!input.maskDescription.empty()) s << " (mask: " << input.maskDescription << ")";
  s << ", of which " << withThousands(counts.repaired()) << " were repaired ("
    << withThousands(counts.repairedNonPositive) << " with a non-positive eigenvalue, "
    << withThousands(counts.repairedAnisotropy) << " beyond the cap)";
  const std::uint64_t outsideBad = counts.zero + counts.nonFinite + counts.noPositiveEigenvalue;
  s << "; " << withThousands(outsideBad) << " voxels with a zero, non-finite or non-positive tensor";
  if (counts.masked) s << " and " << withThousands(counts.masked) << " masked voxels";
  if (counts.belowFaThreshold) s << " and " << withThousands(counts.belowFaThreshold) << " voxels below the FA threshold";
  s << " are outside. ";
  if (seeds.size() <= 3) {
    s << (seeds.size() == 1 ? "Seed: " : "Seeds: ");
    for (std::size_t i = 0; i < seeds.size(); ++i) {
      const Vec3d ras = lpsToRas(g.indexToPhysicalPoint(seeds[i].index.i, seeds[i].index.j, seeds[i].index.k));
      s << (i ? "; " : "") << "voxel " << voxelText(seeds[i].index) << " at RAS " << pointText(ras, 1) << " mm";
    }
  } else {
    s << withThousands(seeds.size()) << " seed voxels";
  }
  if (labelSeedsLeftOut) s << " (" << withThousands(labelSeedsLeftOut) << " label voxels outside the domain left out)";
  s << ". Method: " << methodText(o, memoryDepthOf<VoxelGridDomain>(o));
  if (!o.lanthier) s << " on the " << o.stencil << "-neighbour stencil";
  if (counts.domain < counts.total) s << ", " << connectivityText(o.connectivity);
  if (std::isfinite(o.maxDistance)) s << ", stopping at " << fixed(o.maxDistance, 1) << " mm";
  s << ". Reached " << withThousands(stats.reached) << " of " << withThousands(counts.domain) << " domain voxels";
  if (result.termination == Termination::MaxDistanceReached) s << " before the distance limit";
  if (stats.reached)
    s << "; distances from 0 to " << fixed(stats.maximum, 1) << " mm, median " << fixed(stats.median, 1) << " mm";
  s << ". Took " << fixed(t.total, 2) << " s (read " << fixed(t.read, 2) << ", metric " << fixed(t.metric, 2)
    << ", propagation " << fixed(t.propagate, 2) << ", write " << fixed(t.write, 2) << "). Wrote " << o.output
    << (isVdbPath(o.output)
            ? std::string(" (OpenVDB FloatGrid, voxels placed in RAS millimetres; voxels not reached are inactive)")
            : " (float32 on the input's grid; unreachable voxels = " +
                  (std::isnan(o.unreachableValue) ? std::string("NaN") : jsonNumber(o.unreachableValue)) + ")");
  if (!o.statsPath.empty()) s << " and " << o.statsPath;
  s << ".";
  return s.str();
}

/// The report reads the statistics and a NIfTI distance map: the run's own
/// files when it wrote them to files, copies in a scratch folder otherwise
/// (another format, or a stream such as a FIFO, which cannot be read back).
void writeDistanceReport(ReportRequest& report, const DistanceOptions& o, const RunStatistics& run,
                         const GridGeometry& g, const std::vector<float>& values) {
  const ScratchFolder scratch;
  const std::string statsPath = scratch.statisticsFile(o.statsPath, statisticsJson(run));
  std::string mapPath = o.output;
  try {
    const std::string name = std::filesystem::path(o.output).filename().string();
    const bool nifti = name.size() > 4 && (name.substr(name.size() - 4) == ".nii" ||
                                           (name.size() > 7 && name.substr(name.size() - 7) == ".nii.gz"));
    if (!nifti || files::isStreamOutput(o.output))
      imaging::writeScalarImage(mapPath = scratch.file("distance.nii"), g, values);
  } catch (const std::runtime_error& e) {
    throw ToolError(kExitOutput, e.what());
  }
  report.write({"--stats", statsPath, "--distance", mapPath}, o.quiet);
}

/// `stvd distance FOD --fod-basis NAME`: STVD (the default), Lanthier or
/// Dijkstra under the convexified FOD norm F*, tabulated per voxel (the
/// segment norm for STVD and Lanthier, the 26 neighbour directions for
/// Dijkstra; docs/fod.md), the map written as for tensors.
int runFodDistance(const DistanceOptions& o, int argc, char** argv, Clock::time_point start) {
  Timings t;
  checkRunFiles(o, "FOD input");
  ReportRequest report;
  report.start(o.reportPath, o.reportSubject);

  Clock::time_point phase = Clock::now();
  const FodInput in = readFodInput(o.input, o.fod, o.tensor.maskPath);
  const GridGeometry& g = in.fod.geometry;
  const TensorInput& grid = in.grid;
  const std::vector<std::uint8_t>& inDomain = in.inDomain;
  const imaging::MetricVoxelCounts& counts = in.counts;
  const std::uint64_t voxels = g.voxelCount();
  std::size_t labelSeedsLeftOut = 0;
  const std::vector<Seed> seeds = resolveSeeds(o.input, o, grid, o.tensor.metric, inDomain, labelSeedsLeftOut);
  t.read = secondsSince(phase);

  // STVD's candidates and Lanthier's segments are measured by the segment
  // norm (F* along the lattice of order 2), Dijkstra's steps by F* along
  // the 26 neighbour directions: the same values along those.
  const bool segments = o.lanthier || o.method != Method::Dijkstra;
  const std::uint64_t needed = gridRunMemoryEstimate(o, voxels, counts.domain) + kOutputBytesPerVoxel * voxels +
                               (segments ? sizeof(imaging::FodSegmentNorm::VertexParams)
                                         : sizeof(imaging::FodStencilNorm::VertexParams)) *
                                   voxels;
  const MemoryCheck memory = checkMemory(
      o.input, needed, methodText(o, memoryDepthOf<VoxelGridDomain>(o)) + " on " + withThousands(counts.domain) +
                           " domain voxels of an FOD image",
      !o.memoryCheck);

  phase = Clock::now();
  TableBar tableBar(!o.quiet);
  const FodTable table = makeFodTable(in, o.fod.cost, o.threads, &tableBar, segments);
  t.metric = secondsSince(phase);

  const VoxelGridDomain domain(g, Stencil::byName(o.stencil), inDomain, o.connectivity);
  const std::vector<VertexId> sources = imaging::sourceVertices(domain, seeds);
  phase = Clock::now();
  // Lanthier and STVD measure segments by the segment metric, Dijkstra's
  // steps by the 26 directions (Lanthier cells exist for the former only).
  const PropagationResult result =
      segments ? propagateForTool(o, domain, *table.segments, sources)
               : propagateForTool</*LanthierCells=*/false>(o, domain, table.metric, sources);
  t.propagate = secondsSince(phase);

  report.requireReady();  // nothing is written when the report could not be drawn
  phase = Clock::now();
  const std::vector<float> values = distanceValues(o, result);
  const DistanceStatistics stats = summariseDistances(result.distance);
  const RunStatistics run = commitDistanceOutputs(o, g, result, values, t, start, phase, [&](const Timings& timings) {
    RunStatistics run;
    run.command = "distance";
    run.commandLine = commandLineText(argc, argv);
    run.input = o.input;
    run.output = o.output;
    run.choice = &o;
    run.tensor = &o.tensor;  // its mask
    run.tensorInput = &grid;
    run.counts = counts;
    run.maxDistance = o.maxDistance;
    run.seedLabels = o.seedLabels;
    run.withUnreachableValue = true;
    run.unreachableValue = o.unreachableValue;
    run.seeds = &seeds;
    run.labelSeedsLeftOut = labelSeedsLeftOut;
    run.result = &result;
    run.memory = &memory;
    run.metricParameters = fodMetricParameters(in, o.fod, table);
    run.extraMembers = {fodPrecomputationMember(in, table)};
    run.seconds = {{"read", timings.read}, {"metric", timings.metric}, {"propagate", timings.propagate},
                   {"write", timings.write}, {"total", timings.total}};
    return run;
  });
  if (!o.quiet) {
    std::ostringstream s;
    s << fodInputText(o.input, in, o.fod, table) << ". " << (seeds.size() == 1 ? "Seed" : "Seeds") << ": "
      << withThousands(seeds.size()) << " voxel" << (seeds.size() == 1 ? "" : "s")
      << ". Method: " << methodText(o, memoryDepthOf<VoxelGridDomain>(o));
    if (!o.lanthier) s << " on the " << o.stencil << "-neighbour stencil";
    if (std::isfinite(o.maxDistance)) s << ", stopping at " << fixed(o.maxDistance, 1) << " mm";
    s << ". Reached " << withThousands(stats.reached) << " of " << withThousands(counts.domain) << " domain voxels";
    if (stats.reached)
      s << "; distances from 0 to " << fixed(stats.maximum, 1) << " mm, median " << fixed(stats.median, 1) << " mm";
    s << ". Took " << fixed(t.total, 2) << " s. Wrote " << o.output;
    if (!o.statsPath.empty()) s << " and " << o.statsPath;
    std::cout << s.str() << "." << std::endl;
  }
  if (report.requested()) writeDistanceReport(report, o, run, g, values);
  return kExitOk;
}

}  // namespace

int runDistance(int argc, char** argv) {
  // A TetGen mesh (.node/.ele) goes to the tetrahedral-mesh command.
  for (int i = 2; i < argc; ++i)
    if (isTetMeshInput(argv[i])) return runTetMeshDistance(argc, argv);

  // Polygon surfaces (.obj/.off/.ply, --seed-vertex) have their own path.
  if (isSurfaceDistanceCall(argc, argv)) return runSurfaceDistance(argc, argv);
  const Clock::time_point start = Clock::now();
  const DistanceOptions o = parseDistanceOptions(argc, argv);
  if (o.fod.given()) return runFodDistance(o, argc, argv, start);
  Timings t;

  // Output problems are found before the work, not after it.
  checkRunFiles(o, "tensor input");
  ReportRequest report;
  report.start(o.reportPath, o.reportSubject);

  Clock::time_point phase = Clock::now();
  const TensorInput input = [&] {
    try {
      return readTensorInputNotingWarnings(o.input, o.tensor);
    } catch (const stvd::Error& e) {
      if (e.kind() != stvd::ErrorKind::Input) throw;
      const std::string fod = fodWithoutBasisMessage(o.input);  // an FOD image given without its basis
      if (fod.empty()) throw;
      throw InputError(fod);
    }
  }();
  const GridGeometry& g = input.read.volume.geometry;
  t.read = secondsSince(phase);

  phase = Clock::now();
  imaging::MetricFromTensors built = imaging::buildCheckedMetric(o.input, input, o.tensor);
  imaging::requireNonEmptyDomain(o.input, built.counts, !input.mask.empty(), o.tensor.metric);
  t.metric = secondsSince(phase);

  phase = Clock::now();  // reading a seed label image counts as reading
  std::size_t labelSeedsLeftOut = 0;
  const std::vector<Seed> seeds = resolveSeeds(o.input, o, input, o.tensor.metric, built.inDomain, labelSeedsLeftOut);
  t.read += secondsSince(phase);

  const std::uint64_t voxels = g.voxelCount(), domainVoxels = built.counts.domain;
  const std::uint64_t needed = gridRunMemoryEstimate(o, voxels, domainVoxels) + kOutputBytesPerVoxel * voxels;
  const MemoryCheck memory = checkMemory(
      o.input, needed,
      methodText(o, memoryDepthOf<VoxelGridDomain>(o)) + " on " + withThousands(domainVoxels) + " domain voxels",
      !o.memoryCheck);

  phase = Clock::now();
  const VoxelGridDomain domain(g, Stencil::byName(o.stencil), built.inDomain, o.connectivity);
  const RiemannianMetric metric(std::move(built.metric), &built.inDomain);
  t.metric += secondsSince(phase);

  const std::vector<VertexId> sources = imaging::sourceVertices(domain, seeds);

  phase = Clock::now();
  const PropagationResult result = propagateForTool(o, domain, metric, sources);
  t.propagate = secondsSince(phase);

  report.requireReady();  // nothing is written when the report could not be drawn
  phase = Clock::now();
  const std::vector<float> values = distanceValues(o, result);
  const DistanceStatistics stats = summariseDistances(result.distance);
  const RunStatistics run = commitDistanceOutputs(o, g, result, values, t, start, phase, [&](const Timings& timings) {
    return runStatistics(o, commandLineText(argc, argv), input, built.counts, seeds, labelSeedsLeftOut, result, memory,
                         timings);
  });
  if (!o.quiet)
    std::cout << summaryParagraph(o, input, built.counts, seeds, labelSeedsLeftOut, result, stats, t) << std::endl;
  if (report.requested()) writeDistanceReport(report, o, run, g, values);
  return kExitOk;
}

}  // namespace stvd::tool
