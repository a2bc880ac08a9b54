// Tetrahedral meshes and polygon surfaces from Python arrays: the steps of
// `stvd distance MESH.node` and `stvd distance MESH.obj` without the files,
// with the GIL released while the library works.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "array_access.hpp"
#include "bindings.hpp"
#include "progress_relay.hpp"
#include "propagation_keywords.hpp"
#include "stvd/errors.hpp"
#include "stvd/imaging/tensor_arrays.hpp"
#include "stvd/imaging/tensor_input.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/front_end/mesh_options.hpp"
#include "stvd/front_end/number_text.hpp"
#include "stvd/front_end/propagation_choice.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/surface/manifold_sheets.hpp"
#include "stvd/surface/surface_region_distances.hpp"
#include "stvd/system/parallel_tasks.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/tetmesh/tet_mesh_propagation.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/surface/surface_lanthier.hpp"
#include "stvd/front_end/memory_estimates.hpp"
#include "tensor_field.hpp"

namespace stvd::python {
namespace {

/// One tensor per row of an (N, 6) array in a stated order or an (N, 3, 3)
/// array, in the frame of the mesh's coordinates (no change of frame).
std::vector<SymTensor3> rowTensors(const py::handle& object, std::size_t rows, const std::optional<std::string>& order,
                                   const std::string& name, const std::string& rowKind) {
  const py::array array = numericArray(object, name);
  requireFloatingPoint(array, name);
  const bool matrices = array.ndim() == 3 && array.shape(1) == 3 && array.shape(2) == 3;
  if (!(matrices || (array.ndim() == 2 && array.shape(1) == 6)))
    throw py::value_error(name + ": expected an array of shape (N, 6) or (N, 3, 3), got shape " + shapeText(array));
  if (static_cast<std::size_t>(array.shape(0)) != rows)
    throw py::value_error(name + ": " + std::to_string(array.shape(0)) + " tensors for " + std::to_string(rows) +
                          " " + rowKind + (rows == 1 ? "" : rowKind == "vertex" ? "es" : "s"));
  const py::ssize_t item = array.itemsize();
  imaging::TensorComponentLayout layout;
  layout.voxelStride = {array.strides(0) / item, 0, 0};
  const py::ssize_t last = array.strides(array.ndim() - 1) / item;
  if (matrices) {
    if (order) throw py::value_error(name + ": tensor_order applies to six components per row, not to 3x3 matrices");
    const py::ssize_t row = array.strides(1) / item;
    layout.order = imaging::TensorOrder::Fsl;
    layout.componentOffset = {0, last, 2 * last, row + last, row + 2 * last, 2 * row + 2 * last};
  } else {
    if (!order)
      throw py::value_error(name + ": an array of six values per " + rowKind +
                            " does not say its component order; state it with tensor_order='fsl', 'mrtrix' or "
                            "'lower'");
    imaging::TensorInputOptions parsed;
    parsed.naming = OptionNaming::Keywords;
    imaging::setTensorOrder(parsed, *order);
    layout.order = *parsed.order;
    for (int q = 0; q < 6; ++q) layout.componentOffset[q] = q * last;
  }
  const imaging::Matrix3 identity{1, 0, 0, 0, 1, 0, 0, 0, 1};
  return withFloatView(array, [&](const auto& view) {
    py::gil_scoped_release release;
    return imaging::tensorsFromArray(view.data, {rows, 1, 1}, layout, identity);
  });
}

/// Vertex indices from an (M, width) integer array (width 0: any).
std::vector<std::vector<VertexId>> indexRows(const py::handle& object, std::size_t width, const std::string& name) {
  std::vector<std::vector<VertexId>> rows;
  if (py::isinstance<py::array>(object) || width != 0) {
    const py::array array = numericArray(object, name);
    if (array.dtype().kind() != 'i' && array.dtype().kind() != 'u')
      throw py::type_error(name + ": expected integer vertex indices, got dtype " + std::string(py::str(array.dtype())));
    if (array.ndim() != 2 || (width != 0 && static_cast<std::size_t>(array.shape(1)) != width))
      throw py::value_error(name + ": expected an array of shape (M, " + (width ? std::to_string(width) : "K") +
                            "), got shape " + shapeText(array));
    const py::array_t<long long> values = array.attr("astype")("int64");
    const auto r = values.unchecked<2>();
    for (py::ssize_t m = 0; m < r.shape(0); ++m) {
      std::vector<VertexId> row;
      for (py::ssize_t c = 0; c < r.shape(1); ++c) {
        if (r(m, c) < 0 || r(m, c) >= static_cast<long long>(kNoVertex))
          throw py::value_error(name + ": row " + std::to_string(m) + " holds the vertex index " +
                                std::to_string(r(m, c)));
        row.push_back(static_cast<VertexId>(r(m, c)));
      }
      rows.push_back(std::move(row));
    }
    return rows;
  }
  // A list of polygons of any sizes.
  for (const py::handle& face : object) {
    std::vector<VertexId> row;
    for (const long long v : face.cast<std::vector<long long>>()) {
      if (v < 0 || v >= static_cast<long long>(kNoVertex))
        throw py::value_error(name + ": face " + std::to_string(rows.size()) + " holds the vertex index " +
                              std::to_string(v));
      row.push_back(static_cast<VertexId>(v));
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

/// The seed vertices, sorted and each once; ValueError (NothingToCompute)
/// for one that does not exist or is outside the domain.
std::vector<VertexId> seedVertices(const std::vector<long long>& seeds, const std::vector<std::uint8_t>& inDomain,
                                   const std::string& meshName) {
  if (seeds.empty()) throw OptionError("no seed given (" + keywordOf("--seed-vertex") + "=)");
  std::vector<VertexId> sources;
  for (const long long s : seeds) {
    if (s < 0 || s >= static_cast<long long>(inDomain.size()))
      throw NothingToCompute(meshName + ": seed vertex " + std::to_string(s) + " does not exist (the mesh has " +
                             std::to_string(inDomain.size()) + " vertices)");
    if (!inDomain[s]) throw NothingToCompute(meshName + ": seed vertex " + std::to_string(s) + " is outside the domain");
    sources.push_back(static_cast<VertexId>(s));
  }
  std::sort(sources.begin(), sources.end());
  sources.erase(std::unique(sources.begin(), sources.end()), sources.end());
  return sources;
}

py::dict resultDict(const PropagationResult& r) {
  py::dict d;
  d["distance"] = py::array_t<double>(r.distance.size(), r.distance.data());
  d["predecessor"] = py::array_t<VertexId>(r.predecessor.size(), r.predecessor.data());
  d["finalized_vertices"] = r.finalizedVertices;
  d["relaxed_edges"] = r.relaxedEdges;
  d["cancelled"] = r.termination == Termination::Cancelled;
  return d;
}

py::dict tetMeshPropagate(const py::object& pointsObject, const py::object& tetsObject,
                          const std::vector<long long>& seeds, const py::object& tensorsObject,
                          const std::optional<std::string>& order, const std::optional<std::string>& kind,
                          const std::optional<std::string>& diffusionMetric, const std::optional<double>& maxAnisotropy,
                          const std::optional<double>& faThreshold, const std::optional<std::string>& method,
                          const std::optional<int>& k, const std::optional<std::string>& chainMeasure,
                          const std::optional<int>& steiner, const std::optional<double>& maxDistance,
                          const py::object& progress, bool memoryCheck) {
  const PropagationChoice choice = choiceOf(method, k, chainMeasure, std::nullopt, steiner);
  checkMeshPropagationChoice(choice, "tetrahedron edge", 2);
  const double limit = maxDistanceOf(maxDistance);
  // The order is the rows' (rowTensors); a mesh has no frame of its own.
  const imaging::TensorInputOptions options =
      tensorOptions(std::nullopt, std::nullopt, kind, diffusionMetric, maxAnisotropy, faThreshold);
  const std::vector<Vec3d> points = pointRows(pointsObject, "points");
  std::vector<std::array<VertexId, 4>> tets;
  for (const auto& row : indexRows(tetsObject, 4, "tetrahedra")) tets.push_back({row[0], row[1], row[2], row[3]});
  std::vector<SymTensor3> tensors;
  if (!tensorsObject.is_none()) tensors = rowTensors(tensorsObject, points.size(), order, "tensors", "vertex");
  checkMemory("tetrahedra", tetMeshRunMemoryEstimate(choice, points.size(), tets.size()),
              text::withThousands(points.size()) + " vertices and " + text::withThousands(tets.size()) +
                  " tetrahedra",
              memoryCheck);

  ProgressRelay relay(progress);
  tetmesh::TetMeshPropagation propagation;
  std::vector<std::uint8_t> covered;
  {
    py::gil_scoped_release release;
    std::vector<SymTensor3> metric;
    std::vector<std::uint8_t> inDomain;
    if (tensors.empty()) {  // the Euclidean metric
      metric.assign(points.size(), SymTensor3{1.f, 0.f, 0.f, 1.f, 0.f, 1.f});
      inDomain.assign(points.size(), 1);
    } else {
      imaging::MetricFromTensors built = imaging::buildMetric(tensors, {}, options.metric);
      metric = std::move(built.metric);
      inDomain = std::move(built.inDomain);
    }
    tetmesh::TetrahedraInDomain kept = tetmesh::tetrahedraInDomain(tets, inDomain, "tetrahedra");
    covered = std::move(kept.covered);
    const std::vector<VertexId> sources = seedVertices(seeds, covered, "points");
    propagation = tetmesh::propagateOverTetrahedra(points, kept.tets, metric, covered, sources, choice, limit,
                                                   "tetrahedra", relay.hook());
  }
  relay.rethrowIfFailed();
  py::dict d = resultDict(propagation.result);
  d["edge_count"] = propagation.edgeCount;
  d["in_domain"] = py::array_t<std::uint8_t>(covered.size(), covered.data());
  return d;
}

/// Per-vertex rows for the input's vertices, extended to the copies a
/// non-manifold split made (each takes its vertex's row).
template <class T>
std::vector<T> withCopies(std::vector<T> rows, const ManifoldSheets& sheets) {
  if (rows.size() == sheets.inputVertexCount)
    for (std::size_t v = sheets.inputVertexCount; v < sheets.original.size(); ++v) rows.push_back(rows[sheets.original[v]]);
  return rows;
}

/// The surface of the vertex and face rows as the tool builds it:
/// non-manifold edges and vertices split into manifold sheets (`sheets`
/// says how), the propagation joining them again; checked against the
/// memory a run of `choice` needs. ValueError when it is no surface.
SurfaceDomain surfaceOfRows(const py::object& verticesObject, const py::object& facesObject,
                            const PropagationChoice& choice, bool memoryCheck, ManifoldSheets& sheets) {
  const std::vector<Vec3d> points = pointRows(verticesObject, "vertices");
  PolygonList faces;
  for (const auto& row : indexRows(facesObject, 0, "faces")) faces.add(row.begin(), row.end());
  std::optional<SurfaceDomain> surface;
  try {
    py::gil_scoped_release release;
    surface.emplace(surfaceOfSheets(points, faces, sheets));
  } catch (const SurfaceError& e) {  // not an orientable surface
    throw py::value_error("surface: " + std::string(e.what()));
  }
  checkMemory("vertices", surfaceRunMemoryEstimate(choice, surface->vertexCount(), faces.faceVertex.size()),
              text::withThousands(surface->vertexCount()) + " vertices", memoryCheck);
  return std::move(*surface);
}

RiemannianMetric surfaceMetric(const SurfaceDomain& surface, const ManifoldSheets& sheets, const std::string& kind,
                               const py::object& values, const std::optional<double>& anisotropy,
                               const std::optional<std::string>& order) {
  // Checked by the options' declarations, with messages in keyword names.
  OptionValues given(OptionNaming::Keywords);
  given.set(*findOption(meshOptionDeclarations(), "--metric"), kind);
  if (anisotropy) given.set(*findOption(meshOptionDeclarations(), "--anisotropy"), *anisotropy);
  checkSurfaceMetricChoice(kind, anisotropy.has_value(), OptionNaming::Keywords);
  const bool withValues = kind == "field" || kind == "tensors" || kind == "face-tensors" || kind == "scale";
  if (withValues == values.is_none())
    throw py::value_error(withValues ? "metric='" + kind + "' needs metric_values"
                                     : "metric_values applies to the field, tensors, face-tensors and scale metrics "
                                       "only");
  if (kind == "isotropic") return isotropicSurfaceMetric(surface);
  if (kind == "curvature") return curvatureMetric(surface, *anisotropy);
  if (kind == "field") {
    const std::vector<Vec3d> directions = withCopies(pointRows(values, "metric_values"), sheets);
    if (directions.size() != surface.vertexCount())
      throw py::value_error("metric_values: " + std::to_string(directions.size()) + " directions for " +
                            std::to_string(sheets.inputVertexCount) + " vertices");
    return vectorFieldMetric(surface, directions, 1.0, *anisotropy);
  }
  if (kind == "scale") {
    // A step near a vertex costs its value times its length: s² I.
    const auto scales = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
    if (!scales || scales.ndim() != 1 || static_cast<std::size_t>(scales.shape(0)) != sheets.inputVertexCount)
      throw py::value_error("metric_values: metric='scale' takes one number per vertex (" +
                            std::to_string(sheets.inputVertexCount) + ")");
    std::vector<SymTensor3> tensors;
    for (py::ssize_t v = 0; v < scales.shape(0); ++v) {
      const double s = scales.at(v);
      if (!(s > 0.0) || !std::isfinite(s))
        throw py::value_error("metric_values: vertex " + std::to_string(v) + ": the scale is not a positive number");
      const float s2 = static_cast<float>(s * s);
      tensors.push_back({s2, 0.f, 0.f, s2, 0.f, s2});
    }
    return surfaceMetricFromWorldTensors(surface, withCopies(std::move(tensors), sheets));
  }
  const bool perFace = kind == "face-tensors";
  std::vector<SymTensor3> tensors =
      rowTensors(values, perFace ? surface.faceCount() : sheets.inputVertexCount, order, "metric_values",
                 perFace ? "face" : "vertex");
  if (!perFace) tensors = withCopies(std::move(tensors), sheets);
  return perFace ? surfaceMetricFromFaceTensors(surface, tensors) : surfaceMetricFromWorldTensors(surface, tensors);
}

py::dict surfacePropagate(const py::object& verticesObject, const py::object& facesObject,
                          const std::vector<long long>& seeds, const std::string& metricKind,
                          const py::object& metricValues, const std::optional<double>& anisotropy,
                          const std::optional<std::string>& order, const std::optional<std::string>& method,
                          const std::optional<int>& k, const std::optional<std::string>& chainMeasure,
                          const std::optional<int>& steiner, const std::optional<double>& maxDistance,
                          const py::object& progress, bool memoryCheck) {
  const PropagationChoice choice = choiceOf(method, k, chainMeasure, std::nullopt, steiner);
  checkMeshPropagationChoice(choice, "face edge", 4);
  const double limit = maxDistanceOf(maxDistance);
  ManifoldSheets sheets;
  const SurfaceDomain surface = surfaceOfRows(verticesObject, facesObject, choice, memoryCheck, sheets);
  const RiemannianMetric metric = surfaceMetric(surface, sheets, metricKind, metricValues, anisotropy, order);
  ProgressRelay relay(progress);
  PropagationResult result;
  {
    py::gil_scoped_release release;
    std::vector<VertexId> sources;
    for (const VertexId v : seedVertices(seeds, std::vector<std::uint8_t>(sheets.inputVertexCount, 1), "vertices"))
      for (const VertexId c : sheets.copiesOf(v)) sources.push_back(c);
    if (choice.lanthier && sheets.changed())
      throw OptionError("vertices: " +
                        optionWithValue(propagationOption("--method"), "lanthier", OptionNaming::Keywords) +
                        " does not run on a non-manifold mesh; use method='stvd' or 'dijkstra'");
    if (choice.lanthier) {
      LanthierOptions steiner;
      steiner.steinerPoints = choice.steinerPoints;
      steiner.maxDistance = limit;
      steiner.progress = relay.hook();
      try {
        result = lanthierPropagate(surface, metric, sources, steiner);
      } catch (const std::invalid_argument& e) {  // too large a graph for 32-bit point numbers
        throw OptionError("vertices: " +
                          optionWithValue(propagationOption("--method"), "lanthier", OptionNaming::Keywords) + ": " +
                          e.what());
      }
    } else {
      PropagationOptions options = propagationOptions(choice);
      options.maxDistance = limit;
      options.progress = relay.hook();
      result = propagateOverSheets(surface, metric, sheets, sources, options);
    }
  }
  relay.rethrowIfFailed();
  // The input's vertices: the copies made by the split hold the same values.
  result.distance.resize(sheets.inputVertexCount);
  result.predecessor.resize(sheets.inputVertexCount);
  for (VertexId& p : result.predecessor)
    if (p != kNoVertex) p = sheets.original[p];
  py::dict d = resultDict(result);
  d["component_count"] = surface.componentCount();
  d["split_vertices"] = sheets.splitVertices;
  d["non_manifold_edges"] = sheets.nonManifoldEdges;
  return d;
}

/// Distances between regions and to the nearest region
/// (surface_region_distances.hpp): one propagation per region, on
/// `threads` threads.
py::dict surfaceRegionDistancesPy(const py::object& verticesObject, const py::object& facesObject,
                                  const std::vector<std::vector<long long>>& regions, const std::string& metricKind,
                                  const py::object& metricValues, const std::optional<double>& anisotropy,
                                  const std::optional<std::string>& order, const std::optional<std::string>& method,
                                  const std::optional<int>& k, const std::optional<std::string>& chainMeasure,
                                  const std::optional<double>& maxDistance, unsigned threads, bool keepMaps,
                                  bool memoryCheck) {
  const PropagationChoice choice = choiceOf(method, k, chainMeasure, std::nullopt, std::nullopt);
  checkMeshPropagationChoice(choice, "face edge", 4);
  if (choice.lanthier) throw py::value_error("surface_region_distances runs with method='stvd' or 'dijkstra'");
  if (regions.empty()) throw py::value_error("regions: no region given");
  ManifoldSheets sheets;
  const SurfaceDomain surface = surfaceOfRows(verticesObject, facesObject, choice, memoryCheck, sheets);
  const RiemannianMetric metric = surfaceMetric(surface, sheets, metricKind, metricValues, anisotropy, order);
  const std::vector<std::uint8_t> all(sheets.inputVertexCount, 1);
  std::vector<std::vector<VertexId>> sets;
  for (std::size_t a = 0; a < regions.size(); ++a) {
    if (regions[a].empty()) throw py::value_error("regions: region " + std::to_string(a) + " has no vertex");
    sets.push_back(seedVertices(regions[a], all, "vertices"));
  }
  SurfaceRegionDistances r;
  {
    py::gil_scoped_release release;
    PropagationOptions options = propagationOptions(choice);
    options.maxDistance = maxDistanceOf(maxDistance);
    r = surfaceRegionDistances(surface, metric, sheets, sets, options, threads, keepMaps);
  }
  const std::size_t n = sets.size();
  py::array_t<double> matrix({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(n)});
  std::copy(r.matrix.begin(), r.matrix.end(), matrix.mutable_data());
  std::vector<std::int64_t> nearest(r.nearestRegion.size());
  for (std::size_t v = 0; v < nearest.size(); ++v)
    nearest[v] = r.nearestRegion[v] == SurfaceRegionDistances::kNoRegion ? -1 : static_cast<std::int64_t>(r.nearestRegion[v]);
  py::dict d;
  d["matrix"] = matrix;
  d["nearest_region"] = py::array_t<std::int64_t>(nearest.size(), nearest.data());
  d["nearest_distance"] = py::array_t<double>(r.nearestDistance.size(), r.nearestDistance.data());
  if (keepMaps) {
    py::array_t<double> maps({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(sheets.inputVertexCount)});
    for (std::size_t a = 0; a < n; ++a)
      std::copy(r.maps[a].begin(), r.maps[a].end(), maps.mutable_data() + a * sheets.inputVertexCount);
    d["maps"] = maps;
  }
  return d;
}

/// A surface and its metric built once, queried with many seed sets
/// (stvd.SurfaceSolver): the reusable-solver pattern of the volumes'
/// TensorField, on surfaces. Every query is exactly what surface_distance
/// gives for the same arguments.
class SurfaceSolver {
 public:
  SurfaceSolver(const py::object& verticesObject, const py::object& facesObject, const std::string& metricKind,
                const py::object& metricValues, const std::optional<double>& anisotropy,
                const std::optional<std::string>& order, const std::optional<std::string>& method,
                const std::optional<int>& k, const std::optional<std::string>& chainMeasure,
                const std::optional<double>& maxDistance, bool memoryCheck) {
    const PropagationChoice choice = choiceOf(method, k, chainMeasure, std::nullopt, std::nullopt);
    checkMeshPropagationChoice(choice, "face edge", 4);
    if (choice.lanthier) throw py::value_error("SurfaceSolver runs with method='stvd' or 'dijkstra'");
    options_ = propagationOptions(choice);
    options_.maxDistance = maxDistanceOf(maxDistance);
    surface_.emplace(surfaceOfRows(verticesObject, facesObject, choice, memoryCheck, sheets_));
    metric_.emplace(surfaceMetric(*surface_, sheets_, metricKind, metricValues, anisotropy, order));
  }

  std::size_t vertexCount() const { return sheets_.inputVertexCount; }
  std::size_t splitVertices() const { return sheets_.splitVertices; }

  /// The seeds and all their copies, checked.
  std::vector<VertexId> sources(const std::vector<long long>& seeds) const {
    std::vector<VertexId> out;
    for (const VertexId v : seedVertices(seeds, std::vector<std::uint8_t>(sheets_.inputVertexCount, 1), "vertices"))
      for (const VertexId c : sheets_.copiesOf(v)) out.push_back(c);
    return out;
  }

  PropagationResult run(const std::vector<VertexId>& sources) const {
    return propagateOverSheets(*surface_, *metric_, sheets_, sources, options_);
  }

  py::array_t<double> distance(const std::vector<long long>& seeds) const {
    const std::vector<VertexId> s = sources(seeds);
    PropagationResult r;
    {
      py::gil_scoped_release release;
      r = run(s);
    }
    return py::array_t<double>(sheets_.inputVertexCount, r.distance.data());
  }

  /// One map per seed set, `threads` propagations at once.
  py::array_t<double> distances(const std::vector<std::vector<long long>>& seedSets, unsigned threads) const {
    std::vector<std::vector<VertexId>> sets;
    for (const auto& set : seedSets) sets.push_back(sources(set));
    const std::size_t n = sheets_.inputVertexCount;
    py::array_t<double> maps({static_cast<py::ssize_t>(sets.size()), static_cast<py::ssize_t>(n)});
    double* out = maps.mutable_data();
    {
      py::gil_scoped_release release;
      forEachTaskInParallel(sets.size(), threads, [&](std::size_t i) {
        const PropagationResult r = run(sets[i]);
        std::copy(r.distance.begin(), r.distance.begin() + n, out + i * n);
      });
    }
    return maps;
  }

  /// The path from each target back to the seeds along the propagation's
  /// predecessors: vertex positions, target first; a path between sheets
  /// of a split mesh passes through the vertex they share.
  py::list paths(const std::vector<long long>& seeds, const std::vector<long long>& targets) const {
    const std::vector<VertexId> s = sources(seeds);
    for (const long long t : targets)
      if (t < 0 || static_cast<std::size_t>(t) >= sheets_.inputVertexCount)
        throw py::value_error("targets: vertex " + std::to_string(t) + " does not exist (the surface has " +
                              std::to_string(sheets_.inputVertexCount) + " vertices)");
    PropagationResult r;
    {
      py::gil_scoped_release release;
      r = run(s);
    }
    std::vector<std::uint8_t> isSource(surface_->vertexCount(), 0);
    for (const VertexId v : s) isSource[v] = 1;
    py::list out;
    for (const long long target : targets) {
      std::vector<Vec3d> points;
      if (std::isfinite(r.distance[static_cast<std::size_t>(target)])) {
        VertexId v = static_cast<VertexId>(target);
        for (std::size_t steps = 0; steps <= 2 * r.distance.size(); ++steps) {
          points.push_back(surface_->physicalPoint(v));
          if (isSource[v]) break;
          VertexId next = r.predecessor[v];
          if (next == kNoVertex) {
            // A copy that started a later run: go on from the copy of the
            // same vertex that has a predecessor (or is a seed).
            for (const VertexId c : sheets_.copiesOf(sheets_.original[v]))
              if (c != v && (isSource[c] || r.predecessor[c] != kNoVertex)) next = c;
            if (next == kNoVertex) break;
          }
          v = next;
        }
      }
      py::array_t<double> path({static_cast<py::ssize_t>(points.size()), py::ssize_t{3}});
      auto a = path.mutable_unchecked<2>();
      for (std::size_t i = 0; i < points.size(); ++i) {
        a(i, 0) = points[i].x;
        a(i, 1) = points[i].y;
        a(i, 2) = points[i].z;
      }
      out.append(path);
    }
    return out;
  }

  py::dict regionDistances(const std::vector<std::vector<long long>>& regions, unsigned threads, bool keepMaps) const {
    std::vector<std::vector<VertexId>> sets;
    const std::vector<std::uint8_t> all(sheets_.inputVertexCount, 1);
    for (std::size_t a = 0; a < regions.size(); ++a) {
      if (regions[a].empty()) throw py::value_error("regions: region " + std::to_string(a) + " has no vertex");
      sets.push_back(seedVertices(regions[a], all, "vertices"));
    }
    if (sets.empty()) throw py::value_error("regions: no region given");
    SurfaceRegionDistances r;
    {
      py::gil_scoped_release release;
      r = surfaceRegionDistances(*surface_, *metric_, sheets_, sets, options_, threads, keepMaps);
    }
    return regionDict(r, sets.size(), keepMaps);
  }

  static py::dict regionDict(const SurfaceRegionDistances& r, std::size_t n, bool keepMaps) {
    const std::size_t vertices = r.nearestDistance.size();
    py::array_t<double> matrix({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(n)});
    std::copy(r.matrix.begin(), r.matrix.end(), matrix.mutable_data());
    std::vector<std::int64_t> nearest(vertices);
    for (std::size_t v = 0; v < vertices; ++v)
      nearest[v] = r.nearestRegion[v] == SurfaceRegionDistances::kNoRegion ? -1
                                                                          : static_cast<std::int64_t>(r.nearestRegion[v]);
    py::dict d;
    d["matrix"] = matrix;
    d["nearest_region"] = py::array_t<std::int64_t>(nearest.size(), nearest.data());
    d["nearest_distance"] = py::array_t<double>(r.nearestDistance.size(), r.nearestDistance.data());
    if (keepMaps) {
      py::array_t<double> maps({static_cast<py::ssize_t>(n), static_cast<py::ssize_t>(vertices)});
      for (std::size_t a = 0; a < n; ++a) std::copy(r.maps[a].begin(), r.maps[a].end(), maps.mutable_data() + a * vertices);
      d["maps"] = maps;
    }
    return d;
  }

 private:
  ManifoldSheets sheets_;
  std::optional<SurfaceDomain> surface_;
  std::optional<RiemannianMetric> metric_;
  PropagationOptions options_;
};

}  // namespace

void bindMeshes(py::module_& m) {
  py::class_<SurfaceSolver, std::shared_ptr<SurfaceSolver>>(m, "SurfaceSolver")
      .def(py::init<const py::object&, const py::object&, const std::string&, const py::object&,
                    const std::optional<double>&, const std::optional<std::string>&,
                    const std::optional<std::string>&, const std::optional<int>&,
                    const std::optional<std::string>&, const std::optional<double>&, bool>(),
           py::arg("vertices"), py::arg("faces"), py::arg("metric") = "isotropic",
           py::arg("metric_values") = py::none(), py::arg("anisotropy") = py::none(),
           py::arg("tensor_order") = py::none(), py::arg("method") = py::none(), py::arg("k") = py::none(),
           py::arg("chain_measure") = py::none(), py::arg("max_distance") = py::none(),
           py::arg("memory_check") = true)
      .def_property_readonly("vertex_count", &SurfaceSolver::vertexCount)
      .def_property_readonly("split_vertices", &SurfaceSolver::splitVertices)
      .def("distance", &SurfaceSolver::distance, py::arg("seeds"))
      .def("distances", &SurfaceSolver::distances, py::arg("seed_sets"), py::arg("threads") = 0u)
      .def("paths", &SurfaceSolver::paths, py::arg("seeds"), py::arg("targets"))
      .def("region_distances", &SurfaceSolver::regionDistances, py::arg("regions"), py::arg("threads") = 0u,
           py::arg("keep_maps") = false);
  m.def("surface_region_distances", &surfaceRegionDistancesPy, py::arg("vertices"), py::arg("faces"),
        py::arg("regions"), py::arg("metric") = "isotropic", py::arg("metric_values") = py::none(),
        py::arg("anisotropy") = py::none(), py::arg("tensor_order") = py::none(), py::arg("method") = py::none(),
        py::arg("k") = py::none(), py::arg("chain_measure") = py::none(), py::arg("max_distance") = py::none(),
        py::arg("threads") = 0u, py::arg("keep_maps") = false, py::arg("memory_check") = true);
  m.def("tet_mesh_propagate", &tetMeshPropagate, py::arg("points"), py::arg("tetrahedra"), py::arg("seeds"),
        py::arg("tensors") = py::none(), py::arg("tensor_order") = py::none(), py::arg("tensor_kind") = py::none(),
        py::arg("diffusion_metric") = py::none(), py::arg("max_anisotropy") = py::none(),
        py::arg("fa_threshold") = py::none(), py::arg("method") = py::none(), py::arg("k") = py::none(),
        py::arg("chain_measure") = py::none(), py::arg("steiner") = py::none(), py::arg("max_distance") = py::none(),
        py::arg("progress") = py::none(), py::arg("memory_check") = true);
  m.def("surface_propagate", &surfacePropagate, py::arg("vertices"), py::arg("faces"), py::arg("seeds"),
        py::arg("metric") = "isotropic", py::arg("metric_values") = py::none(), py::arg("anisotropy") = py::none(),
        py::arg("tensor_order") = py::none(), py::arg("method") = py::none(), py::arg("k") = py::none(),
        py::arg("chain_measure") = py::none(), py::arg("steiner") = py::none(), py::arg("max_distance") = py::none(),
        py::arg("progress") = py::none(), py::arg("memory_check") = true);
}

}  // namespace stvd::python
