// FOD images from Python (stvd.fod_distance, stvd.fod_paths,
// stvd.fod_connectivity): the coefficients of a file, an array or a NiBabel
// image on their grid, the convexified FOD norm F* tabulated per voxel along
// the 26 neighbour directions, and Dijkstra from seeds or regions, composed
// in the order `stvd distance|path|connectivity FOD --fod-basis NAME`
// composes them (tools/*_command.cpp, tools/fod_input.cpp; docs/fod.md), so
// that the maps, paths and tables are the tool's. The GIL is released while
// the library works.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "array_access.hpp"
#include "path_records.hpp"
#include "bindings.hpp"
#include "progress_relay.hpp"
#include "propagation_keywords.hpp"
#include "stvd/errors.hpp"
#include "stvd/front_end/memory_estimates.hpp"
#include "stvd/front_end/number_text.hpp"
#include "stvd/front_end/option_declarations.hpp"
#include "stvd/front_end/propagation_choice.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/fod_field.hpp"
#include "stvd/imaging/fod_gfa.hpp"
#include "stvd/imaging/fod_input_options.hpp"
#include "stvd/imaging/fod_metric.hpp"
#include "stvd/imaging/fod_paths.hpp"
#include "stvd/imaging/fod_run_description.hpp"
#include "stvd/imaging/scalar_image.hpp"
#include "stvd/imaging/fod_segment_norm.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/imaging/seed_voxels.hpp"
#include "stvd/imaging/streamline_io.hpp"
#include "stvd/imaging/tensor_arrays.hpp"
#include "stvd/imaging/tensor_input.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/itk/fod_volume_io.hpp"
#include "stvd/itk/image_grid.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/system/parallel_tasks.hpp"
#include "stvd/voxel_grid/label_regions.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "tensor_field.hpp"

namespace stvd::python {
namespace {

/// The FOD keywords, checked by their declarations (fod_input_options.hpp)
/// with messages in keyword names. The basis is required: an FOD's
/// coefficients do not say their basis.
imaging::FodInputOptions fodOptionsOf(const std::optional<std::string>& basis, const std::optional<std::string>& frame,
                                      const std::optional<double>& floor, const std::optional<double>& power) {
  OptionValues values(OptionNaming::Keywords);
  const auto option = [](const char* flag) -> const OptionDeclaration& {
    return *findOption(imaging::fodInputOptionDeclarations(), flag);
  };
  if (basis) values.set(option("--fod-basis"), *basis);
  if (frame) values.set(option("--fod-frame"), *frame);
  if (floor) values.set(option("--fod-floor"), *floor);
  if (power) values.set(option("--fod-power"), *power);
  if (!basis)
    throw OptionError(
        "fod_basis: an FOD's coefficients do not say their basis; state it: 'mrtrix3' for MRtrix's dwi2fod, DIPY's "
        "name for its fits ('descoteaux07_legacy' for DIPY 1.6's CSD and SphHarmModel fits)");
  return imaging::fodInputOptionsOf(values);
}

/// The field of a 4-D array (X, Y, Z, N) on the grid of `affine`.
imaging::FodField fodFieldOfArray(const py::handle& coefficients, const py::handle& affine,
                                  const std::optional<std::array<double, 3>>& zooms, const std::string& name,
                                  const imaging::FodReadOptions& read) {
  const py::array given = numericArray(coefficients, name);
  requireFloatingPoint(given, name);
  if (given.ndim() != 4)
    throw py::value_error(name + ": expected spherical-harmonic coefficients of shape (X, Y, Z, N), got shape " +
                          shapeText(given) +
                          (given.ndim() == 5 ? " (3x3 tensors go to stvd.distance, not to an FOD's call)" : ""));
  if (affine.is_none())
    throw py::value_error(name + ": an array needs affine=, the 4x4 matrix from voxel indices to RAS millimetres");
  // One volume after another, i fastest: the order fodFieldFromVolumes reads.
  const auto values = py::array_t<float, py::array::f_style | py::array::forcecast>::ensure(given);
  const std::array<std::size_t, 3> size{static_cast<std::size_t>(given.shape(0)),
                                        static_cast<std::size_t>(given.shape(1)),
                                        static_cast<std::size_t>(given.shape(2))};
  const std::size_t volumes = static_cast<std::size_t>(given.shape(3));
  GridGeometry g;
  try {
    g = imaging::gridGeometryFromRasAffine(affineOf(affine, "affine"), size, zooms);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(name + ": " + std::string(e.what()));
  }
  const imaging::ShBasis basis = imaging::shBasisOfFile(name, read.basis);
  const imaging::FodFrame frame = read.frame.value_or(imaging::defaultFodFrame(read.basis));
  py::gil_scoped_release release;
  return imaging::fodFieldFromVolumes(name, g, values.data(), static_cast<std::size_t>(values.size()), volumes, basis,
                                      frame, imaging::lpsToFodFrame(frame, g));
}

/// The FOD table's reports (an Interrupter) relayed to the progress hook as
/// reports with no voxel final yet: the caller's function sees the table,
/// and False or Ctrl-C stops it.
class TableProgress final : public Interrupter {
 public:
  TableProgress(std::function<bool(const PropagationProgress&)> hook, std::uint64_t domainVoxels)
      : hook_(std::move(hook)), domainVoxels_(domainVoxels) {}
  bool wasInterrupted(int) override {
    PropagationProgress p;
    p.domainVertices = domainVoxels_;
    return !hook_(p);
  }

 private:
  std::function<bool(const PropagationProgress&)> hook_;
  std::uint64_t domainVoxels_;
};

/// The FOD input of a call: the field (a file when `path` is given, the
/// array otherwise; lmax 4 to 12, as the tool), its grid with the mask as
/// the seeds' and labels' readers take a tensor input's, the domain.
struct FodCallInput {
  std::string name;
  imaging::FodField field;
  imaging::TensorInput grid;
  std::vector<std::uint8_t> inDomain;
  std::uint64_t domainVoxels = 0;
};

FodCallInput fodCallInput(const py::object& coefficients, const py::object& affine,
                          const std::optional<std::array<double, 3>>& zooms, const std::string& givenName,
                          const std::optional<std::string>& path, const imaging::FodInputOptions& fod,
                          const py::object& mask) {
  FodCallInput in;
  in.name = path ? *path : givenName;
  const std::string& name = in.name;
  imaging::FodField& field = in.field;
  if (path) {
    py::gil_scoped_release release;
    field = imaging::readFodVolume(*path, fod.read);
  } else {
    field = fodFieldOfArray(coefficients, affine, zooms, name, fod.read);
  }
  // Six coefficients are also a tensor's six components, and lmax 0 has no
  // direction: lmax 4 and up (CSD's range), as the tool.
  if (field.lmax < 4)
    throw py::value_error(name + ": " + std::to_string(field.coefficientCount()) + " value" +
                          (field.lmax ? "s" : "") + " per voxel (lmax " + std::to_string(field.lmax) + "): " +
                          (field.lmax == 2 ? "six values are a tensor's components; tensors go to stvd.distance"
                                           : "no orientation") +
                          " (FOD images have lmax 4 to 12: 15, 28, 45, 66 or 91 coefficients)");
  const GridGeometry& g = field.geometry;

  // The seeds' and the mask's readers take the grid as a tensor input's.
  imaging::TensorInput& grid = in.grid;
  grid.read.volume.geometry = g;
  if (!mask.is_none())
    imaging::addMask(grid, scalarImageOf(mask, g, "the mask is", name), scalarImageName(mask), name);
  const std::uint64_t voxels = g.voxelCount();
  in.inDomain = grid.mask.empty() ? std::vector<std::uint8_t>(voxels, 1) : grid.mask;
  for (const std::uint8_t inside : in.inDomain) in.domainVoxels += inside != 0;
  if (in.domainVoxels == 0) throw NothingToCompute(name + ": the domain is empty: no voxel inside the mask");
  return in;
}

/// F* tabulated along the 26 neighbour directions of the input's domain
/// voxels (without the GIL), and what it cost; `progress` (may be null)
/// sees the table's blocks and may stop it (Cancelled); `segments`: the
/// segment metric (STVD, Lanthier) instead of the 26 directions.
struct FodCallTable {
  imaging::FodStencilMetric metric;                   ///< Dijkstra's: F* along the 26 neighbour directions
  std::optional<imaging::FodSegmentMetric> segments;  ///< STVD's and Lanthier's, when asked for
  std::size_t directions = 0;
  double seconds = 0.0;
  unsigned threads = 1;
};

FodCallTable fodCallTable(const FodCallInput& in, const imaging::FodCostOptions& cost, unsigned threads,
                          Interrupter* progress = nullptr, bool segments = false) {
  FodCallTable table;
  const GridGeometry& g = in.field.geometry;
  const auto start = std::chrono::steady_clock::now();
  const imaging::FodCostSampler sampler(in.field, imaging::defaultFodSampling(g), cost);
  table.directions = sampler.directionCount();
  if (segments)
    table.segments = imaging::fodSegmentMetric(sampler, &in.inDomain, threads, progress);
  else
    table.metric = imaging::fodStencilMetric(sampler, &in.inDomain, threads, progress);
  table.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  table.threads =
      threadCountFor(threads, (g.voxelCount() + imaging::kFodMetricBlockVoxels - 1) / imaging::kFodMetricBlockVoxels);
  return table;
}

/// F* is tabulated along the 26 neighbour directions: stencils 6, 18, 26.
void checkFodStencil(const PropagationChoice& choice) {
  if (choice.stencil != "6" && choice.stencil != "18" && choice.stencil != "26")
    throw OptionError("stencil='" + choice.stencil +
                      "': the FOD metric is tabulated along the 26 neighbour directions; use 6, 18 or 26");
}

/// The field's generalised fractional anisotropy on its grid (fod_gfa.hpp),
/// as a float32 array (X, Y, Z): what the QC page draws under an FOD run.
py::array_t<float> gfaArray(const imaging::FodField& field) {
  const std::vector<float> gfa = imaging::fodGeneralisedFa(field);
  py::array_t<float> out = newFortranFloatArray(field.geometry.size);
  std::copy(gfa.begin(), gfa.end(), out.mutable_data());
  return out;
}

/// stvd.report's GFA of an FOD file (the background of an FOD run's page
/// made from the tool's files), with the affine of its grid.
py::tuple fodGfaOfFile(const std::string& path, const std::string& basis) {
  const imaging::FodInputOptions fod = fodOptionsOf(basis, std::nullopt, std::nullopt, std::nullopt);
  imaging::FodField field;
  {
    py::gil_scoped_release release;
    field = imaging::readFodVolume(path, fod.read);
  }
  return py::make_tuple(gfaArray(field), affineArray(field.geometry));
}

/// stvd.fod_distance's work: the field (a file when `path` is given, the
/// array otherwise), the domain, the seeds, the table of F*, the method.
py::dict fodDistance(const py::object& coefficients, const py::object& affine,
                     const std::optional<std::array<double, 3>>& zooms, const std::string& givenName,
                     const std::optional<std::string>& path, const std::optional<std::string>& basis,
                     const std::optional<std::string>& frame, const std::optional<double>& floor,
                     const std::optional<double>& power, const py::object& mask,
                     const std::vector<std::array<int, 3>>& seedVoxels,
                     const std::vector<std::array<double, 3>>& seedPoints, bool lps, const py::object& seedLabels,
                     const std::optional<std::string>& method, const std::optional<int>& k,
                     const std::optional<int>& steiner, const std::optional<std::string>& stencil,
                     const std::optional<std::string>& domainConnectivity, const std::optional<double>& maxDistance,
                     double unreachable, unsigned threads, const py::object& progress, bool memoryCheck) {
  const imaging::FodInputOptions fod = fodOptionsOf(basis, frame, floor, power);
  PropagationChoice choice = choiceOf(method, k, std::nullopt, stencil, steiner, domainConnectivity);
  // STVD is the default, as in the tool and as for tensors (docs/fod.md,
  // "The tool"); STVD and Lanthier run on the segment norm.
  checkPropagationChoice(choice, /*lanthierAllowed=*/true);  // k= with STVD only, steiner= with Lanthier
  const bool segments = choice.lanthier || choice.method != Method::Dijkstra;
  checkFodStencil(choice);
  const double limit = maxDistanceOf(maxDistance);
  checkUnreachableValue(unreachable, py::str(py::float_(unreachable)), OptionNaming::Keywords);
  if (seedVoxels.empty() && seedPoints.empty() && seedLabels.is_none())
    throw OptionError(imaging::noSeedMessage(OptionNaming::Keywords));

  FodCallInput in = fodCallInput(coefficients, affine, zooms, givenName, path, fod, mask);
  const std::string& name = in.name;
  const imaging::FodField& field = in.field;
  const GridGeometry& g = field.geometry;
  const imaging::TensorInput& grid = in.grid;
  const std::vector<std::uint8_t>& inDomain = in.inDomain;
  std::optional<imaging::ScalarImage> labels;
  std::string labelsName;
  if (!seedLabels.is_none()) {
    labels = scalarImageOf(seedLabels, g, "the seed labels are", name);
    labelsName = scalarImageName(seedLabels);
  }
  const std::uint64_t voxels = g.voxelCount(), domainVoxels = in.domainVoxels;
  checkMemory(name,
              gridRunMemoryEstimate(choice, voxels, domainVoxels) + sizeof(float) * voxels +
                  (segments ? sizeof(imaging::FodSegmentNorm::VertexParams)
                            : sizeof(imaging::FodStencilNorm::VertexParams)) *
                      voxels,
              methodText(choice, memoryDepthOf<VoxelGridDomain>(choice)) + " on " +
                  text::withThousands(domainVoxels) + " domain voxels of an FOD image",
              memoryCheck);

  ProgressRelay relay(progress);
  PropagationResult result;
  std::vector<imaging::SeedVoxel> seeds;
  std::size_t labelSeedsLeftOut = 0;
  double tableSeconds = 0;
  bool tableCancelled = false;
  std::size_t directions = 0;
  unsigned tableThreads = 1;
  {
    py::gil_scoped_release release;
    seeds = imaging::seedVoxelsAt(name, seedVoxels, seedPoints, lps, grid, imaging::MetricOptions{}, inDomain);
    if (labels) {
      const auto labelled = imaging::labelSeedVoxels(labelsName, *labels, name, g, inDomain, labelSeedsLeftOut);
      seeds.insert(seeds.end(), labelled.begin(), labelled.end());
    }
    // The table reports to the progress function as the run's first
    // reports, no voxel final yet (as Lanthier's setup does); False (or
    // Ctrl-C) stops it.
    TableProgress tableProgress(relay.hook(), in.domainVoxels);
    std::optional<FodCallTable> table;
    try {
      table.emplace(fodCallTable(in, fod.cost, threads, &tableProgress, segments));
    } catch (const Cancelled&) {
      tableCancelled = true;
    }
    if (table) {
      directions = table->directions;
      tableSeconds = table->seconds;
      tableThreads = table->threads;
      const VoxelGridDomain domain(g, Stencil::byName(choice.stencil), inDomain, choice.connectivity);
      const std::vector<VertexId> sources = imaging::sourceVertices(domain, seeds);
      PropagationOptions options = propagationOptions(choice);
      options.maxDistance = limit;
      options.progress = relay.hook();
      if (choice.lanthier) {  // compiled for the segment metric only
        LanthierOptions lanthier;
        lanthier.steinerPoints = choice.steinerPoints;
        lanthier.maxDistance = limit;
        lanthier.progress = relay.hook();
        try {
          result = lanthierPropagate(domain, *table->segments, sources, lanthier);
        } catch (const std::invalid_argument& e) {  // too large a graph
          throw OptionError(name + ": method='lanthier': " + e.what());
        }
      } else if (segments) {
        result = propagate(domain, *table->segments, sources, options);
      } else {
        result = propagate(domain, table->metric, sources, options);
      }
    }
  }
  relay.rethrowIfFailed();  // Ctrl-C or the callback's exception first
  if (tableCancelled)
    throw Cancelled("fod_distance was cancelled by the progress function during the FOD table: no map");
  // stvd.fod_distance returns a map only: a cancelled run has none to give.
  if (result.termination == Termination::Cancelled)
    throw Cancelled("fod_distance was cancelled by the progress function: no map");

  py::array_t<double> distance = newFortranArray(g.size);
  py::array_t<float> map = newFortranFloatArray(g.size);
  {
    double* d = distance.mutable_data();
    float* m = map.mutable_data();
    const float value = static_cast<float>(unreachable);
    for (std::size_t v = 0; v < result.distance.size(); ++v) {
      d[v] = result.distance[v];  // infinity where not reached
      m[v] = std::isfinite(result.distance[v]) ? static_cast<float>(result.distance[v]) : value;  // as the tool
    }
  }
  py::array_t<int> seedArray({static_cast<py::ssize_t>(seeds.size()), py::ssize_t{3}});
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    seedArray.mutable_at(s, 0) = seeds[s].index.i;
    seedArray.mutable_at(s, 1) = seeds[s].index.j;
    seedArray.mutable_at(s, 2) = seeds[s].index.k;
  }
  py::dict out;
  out["distance"] = distance;
  out["distance_map"] = map;
  out["affine"] = affineArray(g);
  out["shape"] = py::make_tuple(g.size[0], g.size[1], g.size[2]);
  out["seeds"] = seedArray;
  out["label_seeds_left_out"] = labelSeedsLeftOut;
  out["fod_basis"] = imaging::shBasisName(field.basis);
  out["fod_frame"] = imaging::fodFrameName(field.frame);
  out["fod_lmax"] = field.lmax;
  out["fod_floor"] = fod.cost.floor;
  out["fod_power"] = fod.cost.power;
  out["fod_directions"] = directions;
  out["fod_norm"] = imaging::fodNormDescription(segments);
  out["gfa"] = gfaArray(field);
  out["table_seconds"] = tableSeconds;
  out["table_threads"] = tableThreads;
  out["domain_voxels"] = domainVoxels;
  out["finalized_vertices"] = result.finalizedVertices;
  out["termination"] = terminationName(result.termination);
  out["method"] = methodName(choice);
  out["stencil"] = choice.stencil;
  return out;
}

/// The grid of FOD paths, which writes them as `stvd path` does
/// (stvd.Paths.save).
struct FodPathGrid {
  GridGeometry geometry;
};

/// Paths and connectivity on FOD images run Dijkstra: its predecessor
/// chains are the paths, whose F*-length is the length reported
/// (docs/fod.md, "Paths and connectivity").
PropagationChoice fodPathChoice(const std::optional<std::string>& method, const std::optional<std::string>& stencil,
                                const std::optional<std::string>& domainConnectivity, const char* what) {
  PropagationChoice choice = choiceOf(method, std::nullopt, std::nullopt, stencil, std::nullopt, domainConnectivity);
  if (choice.lanthier || (method && choice.method != Method::Dijkstra))
    throw OptionError("method='" + *method + "': " + what +
                      " on FOD images run Dijkstra; use method='dijkstra', their default");
  choice.method = Method::Dijkstra;
  checkFodStencil(choice);
  return choice;
}

/// The FOD metric's parameters, as the tool's statistics state them.
void describeFod(py::dict& out, const FodCallInput& in, const imaging::FodInputOptions& fod,
                 const FodCallTable& table) {
  out["fod_basis"] = imaging::shBasisName(in.field.basis);
  out["fod_frame"] = imaging::fodFrameName(in.field.frame);
  out["fod_lmax"] = in.field.lmax;
  out["fod_floor"] = fod.cost.floor;
  out["fod_power"] = fod.cost.power;
  out["fod_directions"] = table.directions;
  out["fod_norm"] = imaging::fodNormDescription(table.segments.has_value());
  out["gfa"] = gfaArray(in.field);
  out["affine"] = affineArray(in.field.geometry);
  out["shape"] = py::make_tuple(in.field.geometry.size[0], in.field.geometry.size[1], in.field.geometry.size[2]);
  out["table_seconds"] = table.seconds;
  out["table_threads"] = table.threads;
  out["domain_voxels"] = in.domainVoxels;
}

/// stvd.fod_paths's work, as `stvd path FOD --fod-basis NAME` composes it
/// (tools/path_command.cpp): the field, the domain, the seeds and targets,
/// the table of F*, Dijkstra, one discrete path per target.
py::dict fodPaths(const py::object& coefficients, const py::object& affine,
                  const std::optional<std::array<double, 3>>& zooms, const std::string& givenName,
                  const std::optional<std::string>& path, const std::optional<std::string>& basis,
                  const std::optional<std::string>& frame, const std::optional<double>& floor,
                  const std::optional<double>& power, const py::object& mask,
                  const std::vector<std::array<int, 3>>& seedVoxels, const std::vector<std::array<double, 3>>& seedPoints,
                  bool lps, const py::object& seedLabels, const std::vector<std::array<int, 3>>& targetVoxels,
                  const std::vector<std::array<double, 3>>& targetPoints, const py::object& targetLabels,
                  const std::optional<std::string>& method, const std::optional<std::string>& stencil,
                  const std::optional<std::string>& domainConnectivity, unsigned threads, const py::object& progress,
                  bool memoryCheck) {
  const imaging::FodInputOptions fod = fodOptionsOf(basis, frame, floor, power);
  const PropagationChoice choice = fodPathChoice(method, stencil, domainConnectivity, "paths");
  if (seedVoxels.empty() && seedPoints.empty() && seedLabels.is_none())
    throw OptionError(imaging::noSeedMessage(OptionNaming::Keywords));
  if (targetVoxels.empty() && targetPoints.empty() && targetLabels.is_none())
    throw OptionError(imaging::noTargetMessage(OptionNaming::Keywords));
  const FodCallInput in = fodCallInput(coefficients, affine, zooms, givenName, path, fod, mask);
  const std::string& name = in.name;
  const GridGeometry& g = in.field.geometry;
  std::optional<imaging::ScalarImage> seedImage;
  std::optional<imaging::LabelImage> targetImage;
  if (!seedLabels.is_none()) seedImage = scalarImageOf(seedLabels, g, "the seed labels are", name);
  if (!targetLabels.is_none()) targetImage = labelImageOf(targetLabels, g, "the target labels are", name);
  const std::string seedLabelsName = seedLabels.is_none() ? "" : scalarImageName(seedLabels);
  const std::string targetLabelsName = targetLabels.is_none() ? "" : scalarImageName(targetLabels);
  const std::uint64_t voxels = g.voxelCount();
  checkMemory(name,
              propagationMemoryEstimate(voxels, in.domainVoxels) + 2 * sizeof(float) * voxels +
                  sizeof(imaging::FodStencilNorm::VertexParams) * voxels,
              methodText(choice, memoryDepthOf<VoxelGridDomain>(choice)) + " on " +
                  text::withThousands(in.domainVoxels) + " domain voxels of an FOD image",
              memoryCheck);

  ProgressRelay relay(progress);
  std::optional<FodCallTable> table;
  std::optional<VoxelGridDomain> domain;
  PropagationResult result;
  std::vector<imaging::PathTarget> targets;
  std::vector<TracedPath> paths;
  std::vector<imaging::SeedVoxel> seeds;
  std::size_t leftOut = 0;
  {
    py::gil_scoped_release release;
    seeds = imaging::seedVoxelsAt(name, seedVoxels, seedPoints, lps, in.grid, imaging::MetricOptions{}, in.inDomain);
    if (seedImage) {
      const auto labelled = imaging::labelSeedVoxels(seedLabelsName, *seedImage, name, g, in.inDomain, leftOut);
      seeds.insert(seeds.end(), labelled.begin(), labelled.end());
    }
    const std::vector<imaging::SeedVoxel> targetSeeds = imaging::seedVoxelsAt(
        name, targetVoxels, targetPoints, lps, in.grid, imaging::MetricOptions{}, in.inDomain, "target");
    table.emplace(fodCallTable(in, fod.cost, threads));
    domain.emplace(g, Stencil::byName(choice.stencil), in.inDomain, choice.connectivity);
    PropagationOptions options = propagationOptions(choice);
    options.progress = relay.hook();
    result = propagate(*domain, table->metric, imaging::sourceVertices(*domain, seeds), options);
    if (result.termination != Termination::Cancelled) {
      for (const imaging::SeedVoxel& t : targetSeeds)
        targets.push_back({domain->vertexAt(t.index.i, t.index.j, t.index.k), t.givenAs});
      if (targetImage) {
        const auto fromLabels =
            imaging::labelTargets(targetLabelsName, *targetImage, name, g, in.inDomain, result.distance);
        targets.insert(targets.end(), fromLabels.begin(), fromLabels.end());
      }
      imaging::requireReachable(name, targets, result.distance);
      for (const imaging::PathTarget& t : targets)
        paths.push_back(imaging::fodGeodesicPath(*domain, table->metric, result, t.vertex));
    }
  }
  relay.rethrowIfFailed();  // Ctrl-C or the callback's exception first
  if (result.termination == Termination::Cancelled)
    throw Cancelled("fod_paths was cancelled by the progress function: no paths");

  py::list records;
  for (std::size_t n = 0; n < targets.size(); ++n) records.append(pathRecord(*domain, targets[n], paths[n], nullptr));
  py::dict out;
  out["paths"] = records;
  out["grid"] = FodPathGrid{g};
  out["affine"] = affineArray(g);
  out["shape"] = py::make_tuple(g.size[0], g.size[1], g.size[2]);
  out["zooms"] = py::make_tuple(g.spacing[0], g.spacing[1], g.spacing[2]);
  out["axis_codes"] = imaging::rasAxisCodes(g);
  // What the QC page draws under the paths, as the tool's page of the run
  // (stvd.report): the distance map, the seeds.
  py::array_t<double> distance = newFortranArray(g.size);
  std::copy(result.distance.begin(), result.distance.end(), distance.mutable_data());
  out["distance"] = distance;
  py::array_t<int> seedArray({static_cast<py::ssize_t>(seeds.size()), py::ssize_t{3}});
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    seedArray.mutable_at(s, 0) = seeds[s].index.i;
    seedArray.mutable_at(s, 1) = seeds[s].index.j;
    seedArray.mutable_at(s, 2) = seeds[s].index.k;
  }
  out["seeds"] = seedArray;
  out["label_seeds_left_out"] = leftOut;
  out["finalized_vertices"] = result.finalizedVertices;
  out["termination"] = terminationName(result.termination);
  out["method"] = methodName(choice);
  out["stencil"] = choice.stencil;
  describeFod(out, in, fod, *table);
  return out;
}

/// stvd.fod_connectivity's work, as `stvd connectivity FOD --fod-basis
/// NAME` composes it (tools/connectivity_command.cpp).
py::dict fodConnectivity(const py::object& coefficients, const py::object& affine,
                         const std::optional<std::array<double, 3>>& zooms, const std::string& givenName,
                         const std::optional<std::string>& path, const std::optional<std::string>& basis,
                         const std::optional<std::string>& frame, const std::optional<double>& floor,
                         const std::optional<double>& power, const py::object& mask, const py::object& labelsSpec,
                         const std::optional<std::string>& method, const std::optional<std::string>& stencil,
                         const std::optional<std::string>& domainConnectivity, unsigned threads,
                         const py::object& progress, bool memoryCheck) {
  const imaging::FodInputOptions fod = fodOptionsOf(basis, frame, floor, power);
  const PropagationChoice choice = fodPathChoice(method, stencil, domainConnectivity, "connectivity and its paths");
  const FodCallInput in = fodCallInput(coefficients, affine, zooms, givenName, path, fod, mask);
  const GridGeometry& g = in.field.geometry;
  const imaging::LabelImage labels = labelImageOf(labelsSpec, g, "the labels are", in.name);
  const std::string labelsName = scalarImageName(labelsSpec);
  ProgressRelay relay(progress);
  std::vector<LabelRegion> regions;
  std::size_t leftOut = 0;
  RegionConnectivity connectivity;
  std::optional<FodCallTable> table;
  bool cancelled = false;
  {
    py::gil_scoped_release release;
    imaging::requireSameGrid(labels.geometry, g, labelsName, "the labels are", in.name);
    regions = regionsInDomain(labelRegions(labels.labels, in.inDomain), labelsName, in.name, leftOut);
    const unsigned threadCount = threadCountFor(threads, regions.size());
    checkMemory(in.name,
                threadCount * propagationMemoryEstimate(g.voxelCount(), in.domainVoxels) +
                    sizeof(imaging::FodStencilNorm::VertexParams) * g.voxelCount(),
                std::to_string(threadCount) + (threadCount == 1 ? " propagation" : " propagations at once") +
                    " on " + text::withThousands(in.domainVoxels) + " domain voxels of an FOD image",
                memoryCheck);
    table.emplace(fodCallTable(in, fod.cost, threads));
    std::vector<std::vector<VertexId>> voxels;
    for (const LabelRegion& r : regions) voxels.push_back(r.voxels);
    const VoxelGridDomain domain(g, Stencil::byName(choice.stencil), in.inDomain, choice.connectivity);
    PropagationOptions options = propagationOptions(choice);
    options.progress = relay.hook();
    options.interrupter = relay.interrupter();  // Ctrl-C between the propagations
    try {
      connectivity = imaging::fodRegionConnectivity(domain, table->metric, voxels, options, threads);
    } catch (const Cancelled&) {
      cancelled = true;
    }
  }
  relay.rethrowIfFailed();  // Ctrl-C or the callback's exception first
  if (cancelled)  // the callback returned False: no partial table
    throw Cancelled("region connectivity was cancelled by the progress function: no table");
  py::dict out = connectivityDict(regions, connectivity, leftOut);
  out["method"] = methodName(choice);
  out["stencil"] = choice.stencil;
  describeFod(out, in, fod, *table);
  return out;
}

}  // namespace

void bindFod(py::module_& m) {
  py::class_<FodPathGrid>(m, "FodPathGrid", "The grid of FOD paths (stvd.fod_paths), which writes them.")
      .def(
          "write_paths",
          [](const FodPathGrid& grid, files::OutputTransaction& outputs, const std::string& path, const py::list& lines,
             const std::vector<double>& geodesic, const std::vector<double>& euclidean,
             const std::optional<std::vector<double>>& meanFa, const py::object& fa) {
            writePathsOnGrid(grid.geometry, outputs, path, lines, geodesic, euclidean, meanFa, fa);
          },
          py::arg("outputs"), py::arg("path"), py::arg("lines"), py::arg("geodesic_mm"), py::arg("euclidean_mm"),
          py::arg("mean_fa") = py::none(), py::arg("fa") = py::none(),
          "Stages the paths (RAS millimetres) in `outputs` as `stvd path` writes them.");
  m.def("fod_paths", &fodPaths, py::arg("coefficients"), py::arg("affine"), py::arg("zooms"), py::arg("name"),
        py::arg("path"), py::arg("fod_basis"), py::arg("fod_frame"), py::arg("fod_floor"), py::arg("fod_power"),
        py::arg("mask"), py::arg("seeds"), py::arg("seed_points"), py::arg("lps"), py::arg("seed_labels"),
        py::arg("targets"), py::arg("target_points"), py::arg("target_labels"), py::arg("method"),
        py::arg("stencil"), py::arg("domain_connectivity"), py::arg("threads"), py::arg("progress"),
        py::arg("memory_check"),
        "Paths under the convexified FOD norm, as `stvd path FOD --fod-basis NAME` (stvd.fod_paths).");
  m.def("fod_connectivity", &fodConnectivity, py::arg("coefficients"), py::arg("affine"), py::arg("zooms"),
        py::arg("name"), py::arg("path"), py::arg("fod_basis"), py::arg("fod_frame"), py::arg("fod_floor"),
        py::arg("fod_power"), py::arg("mask"), py::arg("labels"), py::arg("method"), py::arg("stencil"),
        py::arg("domain_connectivity"), py::arg("threads"), py::arg("progress"), py::arg("memory_check"),
        "Region connectivity under the convexified FOD norm, as `stvd connectivity FOD --fod-basis NAME` "
        "(stvd.fod_connectivity).");
  m.def("fod_distance", &fodDistance, py::arg("coefficients"), py::arg("affine"), py::arg("zooms"),
        py::arg("name"), py::arg("path"), py::arg("fod_basis"), py::arg("fod_frame"), py::arg("fod_floor"),
        py::arg("fod_power"), py::arg("mask"), py::arg("seeds"), py::arg("seed_points"), py::arg("lps"),
        py::arg("seed_labels"), py::arg("method"), py::arg("k"), py::arg("steiner"), py::arg("stencil"), py::arg("domain_connectivity"),
        py::arg("max_distance"), py::arg("unreachable_value"), py::arg("threads"), py::arg("progress"),
        py::arg("memory_check"),
        "Dijkstra, STVD or Lanthier under the convexified FOD norm, as `stvd distance FOD --fod-basis NAME` "
        "(stvd.fod_distance).");
  m.def("fod_gfa", &fodGfaOfFile, py::arg("path"), py::arg("fod_basis"),
        "The generalised fractional anisotropy of an FOD file and its grid's affine (the QC page's background).");
}

}  // namespace stvd::python
