// Tensor volumes from Python: the field (tensors, mask, metric, domain), the
// propagation from seeds, geodesic paths and region connectivity. Each call
// composes the library's functions in the order `stvd distance`, `stvd path`
// and `stvd connectivity` do, with the GIL released while the library works.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "array_access.hpp"
#include "bindings.hpp"
#include "path_records.hpp"
#include "progress_relay.hpp"
#include "propagation_keywords.hpp"
#include "stvd/system/files/output_transaction.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"
#include "stvd/front_end/path_tracing_options.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/imaging/seed_voxels.hpp"
#include "stvd/imaging/streamline_io.hpp"
#include "stvd/voxel_grid/label_regions.hpp"
#include "stvd/front_end/number_text.hpp"
#include "stvd/system/parallel_tasks.hpp"
#include "stvd/front_end/propagation_choice.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "stvd/voxel_grid/region_connectivity.hpp"
#include "stvd/front_end/region_connectivity_options.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"
#include "stvd/front_end/memory_estimates.hpp"
#include "tensor_field.hpp"

namespace stvd::python {
namespace {

/// A finished propagation over a field, with everything paths need.
struct VolumePropagation {
  std::shared_ptr<const TensorField> field;
  PropagationChoice choice;
  VoxelGridDomain domain;
  PropagationResult result;
  std::vector<imaging::SeedVoxel> seeds;
  std::size_t labelSeedsLeftOut = 0;
};

std::vector<std::array<double, 3>> finiteTriples(const std::vector<std::array<double, 3>>& points,
                                                 const std::string& name) {
  for (const auto& p : points)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw py::value_error(name + ": a point is not finite");
  return points;
}

py::dict voxelCounts(const imaging::MetricVoxelCounts& c) {
  py::dict d;
  d["total"] = c.total;
  d["domain"] = c.domain;
  d["masked"] = c.masked;
  d["zero_tensor"] = c.zero;
  d["non_finite_tensor"] = c.nonFinite;
  d["no_positive_eigenvalue"] = c.noPositiveEigenvalue;
  d["below_fa_threshold"] = c.belowFaThreshold;
  d["repaired"] = c.repaired();
  d["repaired_non_positive"] = c.repairedNonPositive;
  d["repaired_anisotropy"] = c.repairedAnisotropy;
  return d;
}

std::vector<std::size_t> gridShape(const GridGeometry& g) { return {g.size[0], g.size[1], g.size[2]}; }

std::shared_ptr<VolumePropagation> propagateField(const std::shared_ptr<const TensorField>& field,
                                                  const std::vector<std::array<int, 3>>& seedVoxels,
                                                  const std::vector<std::array<double, 3>>& seedPoints, bool lps,
                                                  const py::handle& seedLabels, PropagationChoice choice,
                                                  double maxDistance, const py::handle& progress, bool memoryCheck) {
  checkPropagationChoice(choice, /*lanthierAllowed=*/true);
  if (seedVoxels.empty() && seedPoints.empty() && seedLabels.is_none())
    throw OptionError(imaging::noSeedMessage(OptionNaming::Keywords));
  std::optional<imaging::ScalarImage> labels;
  std::string labelsName;
  if (!seedLabels.is_none()) {
    labels = scalarImageOf(seedLabels, field->geometry(), "the seed labels are", field->name);
    labelsName = scalarImageName(seedLabels);
  }
  // The run's state and result, as the tool estimates them, and the float32
  // map distance_map() makes of the result.
  const std::uint64_t voxels = field->geometry().voxelCount(), domainVoxels = field->counts.domain;
  const std::uint64_t needed = gridRunMemoryEstimate(choice, voxels, domainVoxels) + sizeof(float) * voxels;
  checkMemory(field->name, needed,
              methodText(choice, memoryDepthOf<VoxelGridDomain>(choice)) + " on " +
                  text::withThousands(domainVoxels) + " domain voxels",
              memoryCheck);

  ProgressRelay relay(progress);
  std::shared_ptr<VolumePropagation> out;
  {
    py::gil_scoped_release release;
    std::vector<imaging::SeedVoxel> seeds = imaging::seedVoxelsAt(
        field->name, seedVoxels, seedPoints, lps, field->input, field->options.metric, field->inDomain);
    std::size_t leftOut = 0;
    if (labels) {
      const auto labelled =
          imaging::labelSeedVoxels(labelsName, *labels, field->name, field->geometry(), field->inDomain, leftOut);
      seeds.insert(seeds.end(), labelled.begin(), labelled.end());
    }
    out = std::make_shared<VolumePropagation>(VolumePropagation{
        field, choice, VoxelGridDomain(field->geometry(), Stencil::byName(choice.stencil), field->inDomain, choice.connectivity), {},
        std::move(seeds), leftOut});
    const std::vector<VertexId> sources = imaging::sourceVertices(out->domain, out->seeds);
    if (choice.lanthier) {
      LanthierOptions steiner;
      steiner.steinerPoints = choice.steinerPoints;
      steiner.maxDistance = maxDistance;
      steiner.progress = relay.hook();
      try {
        out->result = lanthierPropagate(out->domain, field->metric, sources, steiner);
      } catch (const std::invalid_argument& e) {  // a grid too thin for cubes, or too large a graph
        throw OptionError(field->name + ": " +
                          optionWithValue(propagationOption("--method"), "lanthier", OptionNaming::Keywords) + ": " +
                          e.what());
      }
    } else {
      PropagationOptions options = propagationOptions(choice);
      options.maxDistance = maxDistance;
      options.progress = relay.hook();
      out->result = propagate(out->domain, field->metric, sources, options);
    }
  }
  relay.rethrowIfFailed();
  return out;
}

/// The paths of `stvd path` from a finished propagation, one dict each.
py::list tracePaths(const std::shared_ptr<VolumePropagation>& p, const std::vector<std::array<int, 3>>& targetVoxels,
                    const std::vector<std::array<double, 3>>& targetPoints, bool lps, const py::handle& targetLabels,
                    const std::optional<double>& step, const std::optional<int>& smooth, const std::optional<bool>& refine,
                    bool discrete) {
  checkPropagationChoice(p->choice, /*lanthierAllowed=*/false);
  // Checked by the options' declarations, with messages in keyword names.
  OptionValues values(OptionNaming::Keywords);
  const auto option = [](const char* flag) -> const OptionDeclaration& {
    return *findOption(pathTracingOptionDeclarations(), flag);
  };
  if (step) values.set(option("--step"), *step);
  if (smooth) values.set(option("--smooth"), static_cast<long long>(*smooth));
  if (refine && !*refine) values.set(option("--no-refine"), true);
  const PathTracingOptions tracing = pathTracingOptionsOf(values);
  if (targetVoxels.empty() && targetPoints.empty() && targetLabels.is_none())
    throw OptionError(imaging::noTargetMessage(OptionNaming::Keywords));
  const TensorField& field = *p->field;
  std::optional<imaging::LabelImage> labels;
  std::string labelsName;
  if (!targetLabels.is_none()) {
    labels = labelImageOf(targetLabels, field.geometry(), "the target labels are", field.name);
    labelsName = scalarImageName(targetLabels);
  }

  struct Traced {
    imaging::PathTarget target;
    TracedPath path;
    PathSamples fa;
  };
  std::vector<Traced> traced;
  const bool withFa = field.options.metric.kind == imaging::TensorKind::Diffusion;
  {
    py::gil_scoped_release release;
    std::vector<imaging::PathTarget> targets;
    for (const auto& t : imaging::seedVoxelsAt(field.name, targetVoxels, targetPoints, lps, field.input,
                                               field.options.metric, field.inDomain, "target"))
      targets.push_back({p->domain.vertexAt(t.index.i, t.index.j, t.index.k), t.givenAs});
    if (labels) {
      const auto fromLabels = imaging::labelTargets(labelsName, *labels, field.name, field.geometry(), field.inDomain,
                                                    p->result.distance);
      targets.insert(targets.end(), fromLabels.begin(), fromLabels.end());
    }
    imaging::requireReachable(field.name, targets, p->result.distance);
    for (const imaging::PathTarget& t : targets) {
      Traced one{t, discrete ? discreteGeodesicPath(p->domain, p->result, t.vertex)
                             : traceGeodesicPath(p->domain, field.metric, p->result, t.vertex, tracing),
                 {}};
      if (withFa) one.fa = sampleAlongPath(p->domain, field.fractionalAnisotropy(), one.path.points);
      traced.push_back(std::move(one));
    }
  }

  py::list paths;
  for (const Traced& t : traced) paths.append(pathRecord(p->domain, t.target, t.path, withFa ? &t.fa : nullptr));
  return paths;
}

/// `stvd connectivity` over a field: the label regions, one propagation per
/// region, the matrices.
py::dict connectivity(const std::shared_ptr<const TensorField>& field, const py::handle& labelsSpec,
                      PropagationChoice choice, unsigned threads, const py::handle& progress, bool memoryCheck) {
  checkPropagationChoice(choice, /*lanthierAllowed=*/false);
  const imaging::LabelImage labels = labelImageOf(labelsSpec, field->geometry(), "the labels are", field->name);
  const std::string labelsName = scalarImageName(labelsSpec);
  ProgressRelay relay(progress);
  std::vector<LabelRegion> regions;
  std::size_t leftOut = 0;
  RegionConnectivity table;
  bool cancelled = false;
  {
    py::gil_scoped_release release;
    imaging::requireSameGrid(labels.geometry, field->geometry(), labelsName, "the labels are", field->name);
    regions = regionsInDomain(labelRegions(labels.labels, field->inDomain), labelsName, field->name,
                              leftOut);
    // One propagation at a time on each thread, each with its own state and
    // result, as the tool estimates them.
    const unsigned threadCount = threadCountFor(threads, regions.size());
    checkMemory(field->name,
                threadCount * propagationMemoryEstimate(field->geometry().voxelCount(), field->counts.domain),
                std::to_string(threadCount) + (threadCount == 1 ? " propagation" : " propagations at once") +
                    " on " + text::withThousands(field->counts.domain) + " domain voxels",
                memoryCheck);
    std::vector<std::vector<VertexId>> voxels;
    for (const LabelRegion& r : regions) voxels.push_back(r.voxels);
    const VoxelGridDomain domain(field->geometry(), Stencil::byName(choice.stencil), field->inDomain,
                                 choice.connectivity);
    PropagationOptions options = propagationOptions(choice);
    options.progress = relay.hook();
    options.interrupter = relay.interrupter();  // Ctrl-C between the propagations, in the paths
    try {
      table = regionConnectivity(domain, field->metric, voxels, options, threads);
    } catch (const Cancelled&) {
      cancelled = true;
    }
  }
  relay.rethrowIfFailed();  // Ctrl-C or the callback's exception first
  if (cancelled)  // the callback returned False: no partial table
    throw Cancelled("region connectivity was cancelled by the progress function: no table");
  return connectivityDict(regions, table, leftOut);
}

/// The frame check as Python sees it (stvd.check_tensor_frame, tensor_info).
py::dict frameCheckDict(const imaging::TensorFrameCheck& c) {
  py::dict d;
  d["verdict"] = imaging::tensorFrameVerdictName(c.verdict);
  d["summary"] = imaging::tensorFrameCheckSummary(c);
  d["seeds"] = c.seeds;
  d["best"] = imaging::axisTransformText(c.best);
  d["best_words"] = imaging::axisTransformWords(c.best);
  d["ratio"] = c.ratio;
  d["margin"] = c.margin;
  py::list trials;
  for (const imaging::TensorFrameTrial& t : c.trials)
    trials.append(py::make_tuple(imaging::axisTransformText(t.transform), t.meanLengthMm));
  d["mean_length_mm"] = trials;
  return d;
}

constexpr const char* kPropagationStateTag = "stvd.VolumePropagation/1";

template <class T>
py::bytes bytesOfValues(const std::vector<T>& values) {
  return py::bytes(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

template <class T>
std::vector<T> valuesOfBytes(const py::handle& bytes, std::size_t count, const char* what) {
  const std::string data = bytes.cast<std::string>();
  if (data.size() != count * sizeof(T))
    throw py::value_error(std::string("unpickling stvd: ") + what + " do not fill the grid");
  std::vector<T> values(count);
  if (count) std::memcpy(values.data(), data.data(), data.size());
  return values;
}

/// A propagation as a picklable state: its field (pickled by its own
/// state), the method chosen, the result's arrays and figures and the
/// seeds. The domain is made again from the field and the choice.
py::tuple propagationState(const VolumePropagation& p) {
  const PropagationChoice& c = p.choice;
  const py::tuple choice = py::make_tuple(static_cast<int>(c.method), c.lanthier, c.steinerPoints, c.k,
                                          static_cast<int>(c.chainMeasure), c.chainMeasureGiven, c.stencil,
                                          c.stencilGiven, static_cast<int>(c.connectivity), c.connectivityGiven,
                                          c.memoryCheck, static_cast<int>(c.naming));
  const PropagationResult& r = p.result;
  const py::tuple result = py::make_tuple(bytesOfValues(r.distance), bytesOfValues(r.predecessor),
                                          static_cast<int>(r.termination), r.finalizedVertices, r.relaxedEdges,
                                          r.measuredCandidates, r.refusedCandidates, r.peakStateBytes);
  py::list seeds;
  for (const imaging::SeedVoxel& s : p.seeds) seeds.append(py::make_tuple(s.index.i, s.index.j, s.index.k, s.givenAs));
  return py::make_tuple(kPropagationStateTag, std::const_pointer_cast<TensorField>(p.field), choice, result, seeds,
                        p.labelSeedsLeftOut);
}

std::shared_ptr<VolumePropagation> propagationFromState(const py::tuple& state) {
  if (state.size() != 6 || !py::isinstance<py::str>(state[0]) ||
      state[0].cast<std::string>() != kPropagationStateTag)
    throw py::value_error("unpickling stvd: not the state of an stvd propagation of this version");
  const std::shared_ptr<TensorField> field = state[1].cast<std::shared_ptr<TensorField>>();
  const py::tuple c = state[2].cast<py::tuple>();
  PropagationChoice choice;
  choice.method = static_cast<Method>(c[0].cast<int>());
  choice.lanthier = c[1].cast<bool>();
  choice.steinerPoints = c[2].cast<int>();
  choice.k = c[3].cast<std::optional<int>>();
  choice.chainMeasure = static_cast<ChainMeasure>(c[4].cast<int>());
  choice.chainMeasureGiven = c[5].cast<bool>();
  choice.stencil = c[6].cast<std::string>();
  choice.stencilGiven = c[7].cast<bool>();
  choice.connectivity = static_cast<VoxelConnectivity>(c[8].cast<int>());
  choice.connectivityGiven = c[9].cast<bool>();
  choice.memoryCheck = c[10].cast<bool>();
  choice.naming = static_cast<OptionNaming>(c[11].cast<int>());
  const py::tuple r = state[3].cast<py::tuple>();
  const std::size_t voxels = field->geometry().voxelCount();
  PropagationResult result;
  result.distance = valuesOfBytes<double>(r[0], voxels, "the distances");
  result.predecessor = valuesOfBytes<VertexId>(r[1], voxels, "the predecessors");
  result.termination = static_cast<Termination>(r[2].cast<int>());
  result.finalizedVertices = r[3].cast<std::uint64_t>();
  result.relaxedEdges = r[4].cast<std::uint64_t>();
  result.measuredCandidates = r[5].cast<std::uint64_t>();
  result.refusedCandidates = r[6].cast<std::uint64_t>();
  result.peakStateBytes = r[7].cast<std::uint64_t>();
  std::vector<imaging::SeedVoxel> seeds;
  for (const py::handle s : state[4].cast<py::list>()) {
    const py::tuple t = s.cast<py::tuple>();
    seeds.push_back({VoxelIndex{t[0].cast<std::int32_t>(), t[1].cast<std::int32_t>(), t[2].cast<std::int32_t>()},
                     t[3].cast<std::string>()});
  }
  VoxelGridDomain domain(field->geometry(), Stencil::byName(choice.stencil), field->inDomain, choice.connectivity);
  return std::make_shared<VolumePropagation>(VolumePropagation{field, std::move(choice), std::move(domain),
                                                               std::move(result), std::move(seeds),
                                                               state[5].cast<std::size_t>()});
}

}  // namespace

void bindVolumes(py::module_& m) {
  py::class_<TensorField, std::shared_ptr<TensorField>>(m, "TensorField",
                                                        "Tensors, mask, metric and domain of a tensor volume.")
      .def_static(
          "from_file",
          [](const std::string& path, const py::object& mask, const std::optional<std::string>& order, const std::optional<std::string>& frame,
             const std::optional<std::string>& kind, const std::optional<std::string>& diffusionMetric,
             const std::optional<double>& maxAnisotropy, const std::optional<double>& faThreshold,
             bool acceptImplausible, bool acceptMisaligned) {
            return fieldFromFile(path,
                                 tensorOptions(order, frame, kind, diffusionMetric, maxAnisotropy, faThreshold,
                                               acceptImplausible, acceptMisaligned),
                                 mask);
          },
          py::arg("path"), py::arg("mask") = py::none(),
          py::arg("tensor_order") = py::none(), py::arg("tensor_frame") = py::none(),
          py::arg("tensor_kind") = py::none(), py::arg("diffusion_metric") = py::none(),
          py::arg("max_anisotropy") = py::none(), py::arg("fa_threshold") = py::none(),
          py::arg("accept_implausible_tensors") = false, py::arg("accept_misaligned_tensors") = false)
      .def_static(
          "from_array",
          [](const py::object& tensors, const py::object& affine, const std::optional<std::array<double, 3>>& zooms,
             const std::optional<bool>& niftiIntent, const std::string& name, const py::object& mask,
             const std::optional<std::string>& order,
             const std::optional<std::string>& frame, const std::optional<std::string>& kind,
             const std::optional<std::string>& diffusionMetric, const std::optional<double>& maxAnisotropy,
             const std::optional<double>& faThreshold, bool acceptImplausible, bool acceptMisaligned) {
            return fieldFromArray(tensors, affine, zooms, niftiIntent, name,
                                  tensorOptions(order, frame, kind, diffusionMetric, maxAnisotropy, faThreshold,
                                                acceptImplausible, acceptMisaligned),
                                  mask);
          },
          py::arg("tensors"), py::arg("affine"), py::arg("zooms") = py::none(), py::arg("nifti_intent") = py::none(),
          py::arg("name") = "tensors", py::arg("mask") = py::none(),
          py::arg("tensor_order") = py::none(), py::arg("tensor_frame") = py::none(),
          py::arg("tensor_kind") = py::none(), py::arg("diffusion_metric") = py::none(),
          py::arg("max_anisotropy") = py::none(), py::arg("fa_threshold") = py::none(),
          py::arg("accept_implausible_tensors") = false, py::arg("accept_misaligned_tensors") = false)
      .def(py::pickle([](const TensorField& f) { return fieldState(f); },
                      [](const py::tuple& state) { return fieldFromState(state); }))
      .def_property_readonly("name", [](const TensorField& f) { return f.name; })
      .def_property_readonly("shape", [](const TensorField& f) { return py::tuple(py::cast(gridShape(f.geometry()))); })
      .def_property_readonly("affine", [](const TensorField& f) { return affineArray(f.geometry()); },
                             "4x4 voxel index to RAS millimetres.")
      .def_property_readonly("zooms",
                             [](const TensorField& f) {
                               const auto& s = f.geometry().spacing;
                               return py::make_tuple(s[0], s[1], s[2]);
                             })
      .def_property_readonly("axis_codes", [](const TensorField& f) { return imaging::rasAxisCodes(f.geometry()); })
      .def_property_readonly("voxel_counts", [](const TensorField& f) { return voxelCounts(f.counts); })
      .def_property_readonly("warnings", [](const TensorField& f) { return f.input.warnings; },
                             "What the readers noted about the tensor and mask files, each 'FILE: text'.")
      .def_property_readonly(
          "in_domain",
          [](py::object self) {
            const TensorField& f = self.cast<const TensorField&>();
            return fortranView(f.inDomain.data(), gridShape(f.geometry()), self);
          },
          "uint8 per voxel, 1 inside the domain.")
      .def_property_readonly(
          "fractional_anisotropy",
          [](py::object self) {
            const TensorField& f = self.cast<const TensorField&>();
            {
              py::gil_scoped_release release;
              f.fractionalAnisotropy();
            }
            return fortranView(f.fractionalAnisotropy().data(), gridShape(f.geometry()), self);
          },
          "FA of the tensors as read, in the domain (0 elsewhere).")
      .def_property_readonly("tensor_info",
                             [](const TensorField& f) {
                               const imaging::TensorFileInfo& i = f.input.read.info;
                               const imaging::MetricOptions& metric = f.options.metric;
                               py::dict d;
                               // What came in and how it was read, as given:
                               // a QC page states these (stvd.report).
                               d["input_kind"] = f.inputKind;
                               d["input"] = f.inputDescription;
                               d["layout"] = f.layoutDescription;
                               // 3x3 matrices have no component order.
                               d["order"] = f.matrices ? py::object(py::none())
                                                     : py::object(py::str(imaging::tensorOrderName(i.order)));
                               d["order_was_stated"] = f.options.order.has_value();
                               d["frame"] = imaging::tensorFrameName(i.frame);
                               d["frame_was_stated"] = i.frameWasStated;
                               d["mask"] = f.input.maskDescription;
                               d["tensor_kind"] = imaging::tensorKindName(metric.kind);
                               d["diffusion_metric"] = imaging::diffusionMetricName(metric.diffusionMetric);
                               d["metric_formula"] = imaging::metricFormula(metric.kind, metric.diffusionMetric);
                               const std::optional<double> cap = imaging::anisotropyCap(metric);
                               d["max_anisotropy"] = cap ? py::object(py::float_(*cap)) : py::object(py::none());
                               d["fa_threshold"] = metric.faThreshold ? py::object(py::float_(*metric.faThreshold))
                                                                      : py::object(py::none());
                               d["frame_check"] = frameCheckDict(f.frameCheck);
                               return d;
                             })
      .def(
          "propagate",
          [](const std::shared_ptr<TensorField>& field, const std::vector<std::array<int, 3>>& seeds,
             const std::vector<std::array<double, 3>>& seedPoints, bool lps, const py::object& seedLabels,
             const std::optional<std::string>& method, const std::optional<int>& k,
             const std::optional<std::string>& chainMeasure, const std::optional<std::string>& stencil,
             const std::optional<int>& steiner, const std::optional<double>& maxDistance, const py::object& progress,
             const std::optional<std::string>& domainConnectivity, bool memoryCheck) {
            return propagateField(field, seeds, finiteTriples(seedPoints, "seed_points"), lps, seedLabels,
                                  choiceOf(method, k, chainMeasure, stencil, steiner, domainConnectivity),
                                  maxDistanceOf(maxDistance), progress, memoryCheck);
          },
          py::arg("seeds") = std::vector<std::array<int, 3>>{},
          py::arg("seed_points") = std::vector<std::array<double, 3>>{}, py::arg("lps") = false,
          py::arg("seed_labels") = py::none(), py::arg("method") = py::none(), py::arg("k") = py::none(),
          py::arg("chain_measure") = py::none(), py::arg("stencil") = py::none(), py::arg("steiner") = py::none(),
          py::arg("max_distance") = py::none(), py::arg("progress") = py::none(),
          py::arg("domain_connectivity") = py::none(), py::arg("memory_check") = true)
      .def(
          "connectivity",
          [](const std::shared_ptr<TensorField>& field, const py::object& labels, const std::optional<std::string>& method,
             const std::optional<int>& k, const std::optional<std::string>& chainMeasure,
             const std::optional<std::string>& stencil, const std::optional<int>& threads, const py::object& progress,
             const std::optional<std::string>& domainConnectivity, bool memoryCheck) {
            OptionValues given(OptionNaming::Keywords);
            if (threads)
              given.set(*findOption(regionConnectivityOptionDeclarations(), "--threads"),
                        static_cast<long long>(*threads));
            return connectivity(field, labels,
                                choiceOf(method, k, chainMeasure, stencil, std::nullopt, domainConnectivity),
                                regionThreadsOf(given), progress, memoryCheck);
          },
          py::arg("labels"), py::arg("method") = py::none(), py::arg("k") = py::none(),
          py::arg("chain_measure") = py::none(), py::arg("stencil") = py::none(), py::arg("threads") = py::none(),
          py::arg("progress") = py::none(), py::arg("domain_connectivity") = py::none(),
          py::arg("memory_check") = true);

  py::class_<VolumePropagation, std::shared_ptr<VolumePropagation>>(m, "VolumePropagation")
      .def(py::pickle([](const VolumePropagation& p) { return propagationState(p); },
                      [](const py::tuple& state) { return propagationFromState(state); }))
      .def_property_readonly("field", [](const VolumePropagation& p) { return std::const_pointer_cast<TensorField>(p.field); })
      .def_property_readonly(
          "distance",
          [](py::object self) {
            const VolumePropagation& p = self.cast<const VolumePropagation&>();
            return fortranView(p.result.distance.data(), gridShape(p.field->geometry()), self);
          },
          "float64 millimetres per voxel, inf where not reached (read-only view).")
      .def_property_readonly(
          "predecessor",
          [](py::object self) {
            const VolumePropagation& p = self.cast<const VolumePropagation&>();
            return fortranView(p.result.predecessor.data(), gridShape(p.field->geometry()), self);
          },
          "uint32 linear voxel index (i + nx*(j + ny*k)) of each voxel's predecessor, the voxel its distance was "
          "measured from (with STVD's segment measure the start of the straight segment that gave it, not "
          "necessarily a neighbour); NO_VERTEX for seeds and voxels not reached.")
      .def(
          "distance_map",
          [](const VolumePropagation& p, double unreachable) {
            checkUnreachableValue(unreachable, py::str(py::float_(unreachable)), OptionNaming::Keywords);
            py::array_t<float> map = newFortranFloatArray(p.field->geometry().size);
            float* out = map.mutable_data();
            const float value = static_cast<float>(unreachable);
            py::gil_scoped_release release;
            const std::vector<double>& d = p.result.distance;
            for (std::size_t v = 0; v < d.size(); ++v) out[v] = std::isfinite(d[v]) ? static_cast<float>(d[v]) : value;
            return map;
          },
          py::arg("unreachable_value"), "float32 distances as `stvd distance` writes them.")
      .def(
          "write_distance_map",
          [](const VolumePropagation& p, files::OutputTransaction& outputs, const std::string& path,
             double unreachable) {
            checkUnreachableValue(unreachable, py::str(py::float_(unreachable)), OptionNaming::Keywords);
            // The values and the writer of `stvd distance`: the same bytes.
            const float value = static_cast<float>(unreachable);
            py::gil_scoped_release release;
            const std::vector<double>& d = p.result.distance;
            std::vector<float> values(d.size());
            for (std::size_t v = 0; v < d.size(); ++v) values[v] = std::isfinite(d[v]) ? static_cast<float>(d[v]) : value;
            imaging::writeScalarImage(outputs, path, p.field->geometry(), values);
          },
          py::arg("outputs"), py::arg("path"), py::arg("unreachable_value"),
          "Stages the float32 distance map in `outputs` as `stvd distance` writes it.")
      .def(
          "write_paths",
          [](const VolumePropagation& p, files::OutputTransaction& outputs, const std::string& path,
             const py::list& lines, const std::vector<double>& geodesic, const std::vector<double>& euclidean,
             const std::optional<std::vector<double>>& meanFa, const py::object& fa) {
            writePathsOnGrid(p.field->geometry(), outputs, path, lines, geodesic, euclidean, meanFa, fa);
          },
          py::arg("outputs"), py::arg("path"), py::arg("lines"), py::arg("geodesic_mm"), py::arg("euclidean_mm"),
          py::arg("mean_fa") = py::none(), py::arg("fa") = py::none(),
          "Stages the paths (RAS millimetres) in `outputs` as `stvd path` writes them.")
      .def_property_readonly("termination", [](const VolumePropagation& p) { return terminationName(p.result.termination); })
      .def_property_readonly("finalized_vertices", [](const VolumePropagation& p) { return p.result.finalizedVertices; })
      .def_property_readonly("relaxed_edges", [](const VolumePropagation& p) { return p.result.relaxedEdges; })
      .def_property_readonly("peak_state_bytes", [](const VolumePropagation& p) { return p.result.peakStateBytes; })
      .def_property_readonly("seeds",
                             [](const VolumePropagation& p) {
                               py::array_t<int> a({static_cast<py::ssize_t>(p.seeds.size()), py::ssize_t{3}});
                               auto w = a.mutable_unchecked<2>();
                               for (std::size_t s = 0; s < p.seeds.size(); ++s) {
                                 w(s, 0) = p.seeds[s].index.i;
                                 w(s, 1) = p.seeds[s].index.j;
                                 w(s, 2) = p.seeds[s].index.k;
                               }
                               return a;
                             })
      .def_property_readonly("label_seeds_left_out", [](const VolumePropagation& p) { return p.labelSeedsLeftOut; })
      .def_property_readonly("method", [](const VolumePropagation& p) { return methodName(p.choice); })
      .def_property_readonly("method_text", [](const VolumePropagation& p) { return methodText(p.choice, memoryDepthOf<VoxelGridDomain>(p.choice)); })
      .def_property_readonly("k", [](const VolumePropagation& p) {
        return p.choice.lanthier ? py::object(py::none()) : py::object(py::int_(memoryDepthOf<VoxelGridDomain>(p.choice)));
      })
      .def_property_readonly("chain_measure", [](const VolumePropagation& p) { return chainMeasureName(p.choice.chainMeasure); })
      .def_property_readonly("stencil", [](const VolumePropagation& p) { return p.choice.stencil; })
      .def_property_readonly("domain_connectivity",
                             [](const VolumePropagation& p) { return static_cast<int>(p.choice.connectivity); })
      .def(
          "trace_paths",
          [](const std::shared_ptr<VolumePropagation>& p, const std::vector<std::array<int, 3>>& targets,
             const std::vector<std::array<double, 3>>& targetPoints, bool lps, const py::object& targetLabels,
             const std::optional<double>& step, const std::optional<int>& smooth, const std::optional<bool>& refine,
             bool discrete) {
            return tracePaths(p, targets, finiteTriples(targetPoints, "target_points"), lps, targetLabels, step, smooth,
                              refine, discrete);
          },
          py::arg("targets") = std::vector<std::array<int, 3>>{},
          py::arg("target_points") = std::vector<std::array<double, 3>>{}, py::arg("lps") = false,
          py::arg("target_labels") = py::none(), py::arg("step") = py::none(), py::arg("smooth") = py::none(),
          py::arg("refine") = py::none(), py::arg("discrete") = false);
}

}  // namespace stvd::python
