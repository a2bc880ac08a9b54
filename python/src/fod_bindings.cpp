// FOD images from Python (stvd.fod_distance): the coefficients of a file, an
// array or a NiBabel image on their grid, the convexified FOD norm F*
// tabulated per voxel along the 26 neighbour directions, and Dijkstra from
// seeds, composed in the order `stvd distance FOD --fod-basis NAME` composes
// them (tools/distance_command.cpp, runFodDistance; docs/fod.md), so that
// the map is the tool's. The GIL is released while the library works.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "array_access.hpp"
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
#include "stvd/imaging/fod_input_options.hpp"
#include "stvd/imaging/fod_metric.hpp"
#include "stvd/imaging/fod_segment_norm.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/imaging/seed_voxels.hpp"
#include "stvd/imaging/streamline_io.hpp"
#include "stvd/imaging/tensor_arrays.hpp"
#include "stvd/imaging/tensor_input.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/itk/fod_volume_io.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/system/parallel_tasks.hpp"
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
  // Dijkstra is the default for FOD images, as in the tool (docs/fod.md,
  // "STVD and Lanthier"); STVD and Lanthier run on the segment norm.
  if (!method) choice.method = Method::Dijkstra;
  checkPropagationChoice(choice, /*lanthierAllowed=*/true);  // k= with STVD only, steiner= with Lanthier
  const bool segments = choice.lanthier || choice.method != Method::Dijkstra;
  if (choice.stencil != "6" && choice.stencil != "18" && choice.stencil != "26")
    throw OptionError("stencil='" + choice.stencil +
                      "': the FOD metric is tabulated along the 26 neighbour directions; use 6, 18 or 26");
  const double limit = maxDistanceOf(maxDistance);
  checkUnreachableValue(unreachable, py::str(py::float_(unreachable)), OptionNaming::Keywords);
  if (seedVoxels.empty() && seedPoints.empty() && seedLabels.is_none())
    throw OptionError(imaging::noSeedMessage(OptionNaming::Keywords));

  const std::string name = path ? *path : givenName;
  imaging::FodField field;
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
  imaging::TensorInput grid;
  grid.read.volume.geometry = g;
  if (!mask.is_none())
    imaging::addMask(grid, scalarImageOf(mask, g, "the mask is", name), scalarImageName(mask), name);
  std::optional<imaging::ScalarImage> labels;
  std::string labelsName;
  if (!seedLabels.is_none()) {
    labels = scalarImageOf(seedLabels, g, "the seed labels are", name);
    labelsName = scalarImageName(seedLabels);
  }
  const std::uint64_t voxels = g.voxelCount();
  const std::vector<std::uint8_t> inDomain = grid.mask.empty() ? std::vector<std::uint8_t>(voxels, 1) : grid.mask;
  std::uint64_t domainVoxels = 0;
  for (const std::uint8_t inside : inDomain) domainVoxels += inside != 0;
  if (domainVoxels == 0) throw NothingToCompute(name + ": the domain is empty: no voxel inside the mask");
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
  std::size_t directions = 0;
  unsigned tableThreads = 1;
  {
    py::gil_scoped_release release;
    seeds = imaging::seedVoxelsAt(name, seedVoxels, seedPoints, lps, grid, imaging::MetricOptions{}, inDomain);
    if (labels) {
      const auto labelled = imaging::labelSeedVoxels(labelsName, *labels, name, g, inDomain, labelSeedsLeftOut);
      seeds.insert(seeds.end(), labelled.begin(), labelled.end());
    }
    const auto start = std::chrono::steady_clock::now();
    const imaging::FodCostSampler sampler(field, imaging::defaultFodSamplingDirections(g), fod.cost);
    directions = sampler.directions().size();
    tableThreads =
        threadCountFor(threads, (voxels + imaging::kFodMetricBlockVoxels - 1) / imaging::kFodMetricBlockVoxels);
    const VoxelGridDomain domain(g, Stencil::byName(choice.stencil), inDomain, choice.connectivity);
    // The table of the method's metric (as the tool), then the propagation.
    const auto run = [&](const auto& metric) {
      tableSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const std::vector<VertexId> sources = imaging::sourceVertices(domain, seeds);
      // Lanthier runs on the segment metric only (compiled for it).
      if constexpr (std::is_same_v<std::decay_t<decltype(metric)>, imaging::FodSegmentMetric>) {
        if (choice.lanthier) {
          LanthierOptions lanthier;
          lanthier.steinerPoints = choice.steinerPoints;
          lanthier.maxDistance = limit;
          lanthier.progress = relay.hook();
          try {
            result = lanthierPropagate(domain, metric, sources, lanthier);
          } catch (const std::invalid_argument& e) {  // too large a graph
            throw OptionError(name + ": method='lanthier': " + e.what());
          }
          return;
        }
      }
      PropagationOptions options = propagationOptions(choice);
      options.maxDistance = limit;
      options.progress = relay.hook();
      result = propagate(domain, metric, sources, options);
    };
    if (segments)
      run(imaging::fodSegmentMetric(sampler, &inDomain, threads));
    else
      run(imaging::fodStencilMetric(sampler, &inDomain, threads));
  }
  relay.rethrowIfFailed();  // Ctrl-C or the callback's exception first
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
  const std::array<double, 16> ras = imaging::voxelToRas(g);
  py::array_t<double> affineOut({4, 4});
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) affineOut.mutable_at(r, c) = ras[4 * r + c];
  py::array_t<int> seedArray({static_cast<py::ssize_t>(seeds.size()), py::ssize_t{3}});
  for (std::size_t s = 0; s < seeds.size(); ++s) {
    seedArray.mutable_at(s, 0) = seeds[s].index.i;
    seedArray.mutable_at(s, 1) = seeds[s].index.j;
    seedArray.mutable_at(s, 2) = seeds[s].index.k;
  }
  py::dict out;
  out["distance"] = distance;
  out["distance_map"] = map;
  out["affine"] = affineOut;
  out["seeds"] = seedArray;
  out["label_seeds_left_out"] = labelSeedsLeftOut;
  out["fod_basis"] = imaging::shBasisName(field.basis);
  out["fod_frame"] = imaging::fodFrameName(field.frame);
  out["fod_lmax"] = field.lmax;
  out["fod_floor"] = fod.cost.floor;
  out["fod_power"] = fod.cost.power;
  out["fod_directions"] = directions;
  out["table_seconds"] = tableSeconds;
  out["table_threads"] = tableThreads;
  out["domain_voxels"] = domainVoxels;
  out["finalized_vertices"] = result.finalizedVertices;
  out["termination"] = terminationName(result.termination);
  out["method"] = methodName(choice);
  out["stencil"] = choice.stencil;
  return out;
}

}  // namespace

void bindFod(py::module_& m) {
  m.def("fod_distance", &fodDistance, py::arg("coefficients"), py::arg("affine"), py::arg("zooms"),
        py::arg("name"), py::arg("path"), py::arg("fod_basis"), py::arg("fod_frame"), py::arg("fod_floor"),
        py::arg("fod_power"), py::arg("mask"), py::arg("seeds"), py::arg("seed_points"), py::arg("lps"),
        py::arg("seed_labels"), py::arg("method"), py::arg("k"), py::arg("steiner"), py::arg("stencil"), py::arg("domain_connectivity"),
        py::arg("max_distance"), py::arg("unreachable_value"), py::arg("threads"), py::arg("progress"),
        py::arg("memory_check"),
        "Dijkstra, STVD or Lanthier under the convexified FOD norm, as `stvd distance FOD --fod-basis NAME` "
        "(stvd.fod_distance).");
}

}  // namespace stvd::python
