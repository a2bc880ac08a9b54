// `stvd distance MESH.node`: Dijkstra or STVD over the edges of a TetGen
// tetrahedral mesh, with the metric from the mesh's own attributes or
// sampled from a tensor image, written per vertex as .vtk, .vtu or .csv.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>

#include "command_line.hpp"
#include "command_options.hpp"
#include "geodesic_options.hpp"
#include "memory_check.hpp"
#include "tool_run_files.hpp"
#include "stvd/system/files/output_transaction.hpp"
#include "stvd/errors.hpp"
#include "stvd/imaging/metric_sampling.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "option_help.hpp"
#include "stvd/itk/image_grid.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "stvd/tetmesh/grid_resampling.hpp"
#include "stvd/tetmesh/tet_mesh.hpp"
#include "stvd/tetmesh/tet_mesh_options.hpp"
#include "stvd/tetmesh/tet_mesh_propagation.hpp"
#include "stvd/tetmesh/tet_mesh_writers.hpp"
#include "stvd/cell_mesh/cell_mesh_propagation.hpp"
#include "stvd/front_end/memory_estimates.hpp"
#include "tet_mesh_commands.hpp"

namespace stvd::tool {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

const char* kTetDistanceUsage =
    "Usage: stvd distance MESH.node -o OUTPUT [options]\n"
    "\n"
    "Anisotropic geodesic distance from seed vertices over a tetrahedral mesh in TetGen's format\n"
    "(MESH.node with MESH.ele, and MESH.face when present; MESH.ele may be given instead; indices\n"
    "0- or 1-based as the files number them). The graph is the mesh's edges; STVD sums 3D edge\n"
    "vectors along the predecessor chain (Campen et al. 2013, section 6.2). Coordinates and\n"
    "distances are in the mesh's units (millimetres for anatomy). See docs/tet_meshes.md.\n"
    "\n";

std::string tetDistanceHelp() { return kTetDistanceUsage + tetMeshOptionsHelp(); }

/// The propagation's options with the library's defaults, and the mesh's
/// own.
struct TetDistanceOptions : PropagationChoice {
  std::string input;
  std::string output;
  std::vector<long long> seedVertices;
  std::vector<std::array<double, 3>> seedPoints;
  bool seedAtPoint = false;
  bool lps = false;
  std::string tensors;  // "", "node", "ele" or an image path
  int tensorAttribute = tetmesh::kDefaultFirstTensorAttribute;
  bool maskOutsideImage = false;  // --outside-image mask
  double maxDistance = std::numeric_limits<double>::infinity();
  TensorInputOptions tensor;
  double unreachableValue = kDefaultUnreachableValue;
  std::string reference;
  bool quiet = false;
};

TetDistanceOptions parseOptions(int argc, char** argv) {
  const CommandLine line = readCommandLine(kTetMeshDistanceCommand, argc, argv, 2, tetDistanceHelp);
  const OptionValues& v = line.values;
  TetDistanceOptions o;
  static_cast<PropagationChoice&>(o) = propagationChoiceOf(v);
  o.input = line.input;
  o.output = v.text("--output").value_or("");
  for (const OptionValue& given : v.all("--seed-vertex")) o.seedVertices.push_back(std::get<long long>(given));
  o.seedPoints = imaging::pointsOf(v, "--seed-point");
  o.seedAtPoint = v.text("--seed-at") == "point";
  o.lps = v.has("--lps");
  o.tensors = v.text("--tensors").value_or("");
  o.tensorAttribute = static_cast<int>(v.integer("--tensor-attribute").value_or(o.tensorAttribute));
  o.maskOutsideImage = v.text("--outside-image") == "mask";
  o.maxDistance = v.number("--max-distance").value_or(o.maxDistance);
  o.reference = v.text("--reference").value_or("");
  o.unreachableValue = v.number("--unreachable-value").value_or(o.unreachableValue);
  o.tensor = imaging::tensorInputOptionsOf(v);
  o.quiet = v.has("--quiet");
  if (o.input.empty()) usageError("no input mesh (see stvd distance --help)");
  if (o.output.empty()) usageError("no output: -o FILE (.vtk, .vtu or .csv) is required");
  if (o.seedVertices.empty() && o.seedPoints.empty())
    usageError("no seed: give --seed-vertex or --seed-point");
  checkMeshPropagationChoice(o, "tetrahedron edge", 2);
  tetmesh::TetMeshOutputFormat format;
  if (imaging::hasImageExtension(o.output)) {
    checkImageOutputSpelling(o.output);
    if (o.reference.empty())
      usageError("-o " + o.output + ": an image output needs --reference IMAGE to take its grid from");
  } else if (!tetmesh::outputFormatOf(o.output, format)) {
    usageError("-o " + o.output + ": a tetrahedral mesh is written as .vtk, .vtu or .csv (or an image with --reference)");
  } else if (!o.reference.empty()) {
    usageError("--reference is for image outputs (.nii, .nii.gz, .nrrd, .nhdr)");
  }
  return o;
}

/// The six attributes starting at `first` of row `row` as a tensor.
SymTensor3 attributeTensor(const std::vector<double>& attributes, std::size_t perRow, std::size_t row,
                           std::size_t first, imaging::TensorOrder order) {
  float c[6];
  for (int i = 0; i < 6; ++i) c[i] = static_cast<float>(attributes[row * perRow + first + i]);
  return imaging::tensorFromComponents(c, order);
}

/// Per-vertex tensors (before the metric is built from them) and, for an
/// image, which vertices it covers. An empty result means "Euclidean".
struct VertexTensors {
  std::vector<SymTensor3> tensors;
  /// For an image source: the sampled metric is final (already built on the
  /// voxels), and these vertices are in its domain.
  bool alreadyMetric = false;
  std::vector<std::uint8_t> inDomain;
  std::string description = "Euclidean (identity metric)";
};

VertexTensors tensorsFromAttributes(const TetDistanceOptions& o, const tetmesh::TetMesh& mesh,
                                    const std::string& nodeFile, const std::string& eleFile) {
  VertexTensors out;
  const imaging::TensorOrder order = o.tensor.order.value_or(imaging::kDefaultAttributeTensorOrder);
  const std::size_t first = static_cast<std::size_t>(o.tensorAttribute);
  if (o.tensors == "node") {
    if (mesh.pointAttributeCount < first + 6)
      throw ToolError(kExitInput, nodeFile + ": --tensors node needs six point attributes from attribute " +
                                      std::to_string(first) + ", the file has " +
                                      std::to_string(mesh.pointAttributeCount));
    out.tensors.resize(mesh.vertexCount());
    for (std::size_t v = 0; v < mesh.vertexCount(); ++v)
      out.tensors[v] = attributeTensor(mesh.pointAttributes, mesh.pointAttributeCount, v, first, order);
    out.description = "six .node attributes from " + std::to_string(first) + " (" +
                      imaging::tensorOrderComponents(order) + ")";
    return out;
  }
  if (mesh.tetAttributeCount < first + 6)
    throw ToolError(kExitInput, eleFile + ": --tensors ele needs six tetrahedron attributes from attribute " +
                                    std::to_string(first) + ", the file has " + std::to_string(mesh.tetAttributeCount));
  // Volume-weighted arithmetic mean of the incident tetrahedra's tensors: a
  // convex combination, so positive-definite tensors stay positive-definite.
  std::vector<double> sum(6 * mesh.vertexCount(), 0.0), weight(mesh.vertexCount(), 0.0);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& c = mesh.tets[t];
    const double volume =
        std::abs(tetmesh::signedVolume(mesh.points[c[0]], mesh.points[c[1]], mesh.points[c[2]], mesh.points[c[3]]));
    const SymTensor3 tensor = attributeTensor(mesh.tetAttributes, mesh.tetAttributeCount, t, first, order);
    const double comps[6] = {tensor.xx, tensor.xy, tensor.xz, tensor.yy, tensor.yz, tensor.zz};
    for (VertexId v : c) {
      for (int i = 0; i < 6; ++i) sum[6 * v + i] += volume * comps[i];
      weight[v] += volume;
    }
  }
  out.tensors.assign(mesh.vertexCount(), SymTensor3{});  // zero: outside the domain when in no tetrahedron
  for (std::size_t v = 0; v < mesh.vertexCount(); ++v) {
    if (weight[v] <= 0.0) continue;
    const double* s = &sum[6 * v];
    const double w = weight[v];
    out.tensors[v] = {float(s[0] / w), float(s[1] / w), float(s[2] / w), float(s[3] / w), float(s[4] / w),
                      float(s[5] / w)};
  }
  out.description = "six .ele attributes from " + std::to_string(first) + " (" +
                    imaging::tensorOrderComponents(order) + "), volume-weighted mean at the vertices";
  return out;
}

VertexTensors tensorsFromImage(const TetDistanceOptions& o, const tetmesh::TetMesh& mesh) {
  VertexTensors out;
  const TensorInput input = readTensorInputNotingWarnings(o.tensors, o.tensor);
  const imaging::MetricFromTensors built = imaging::buildCheckedMetric(o.tensors, input, o.tensor);
  std::vector<Vec3d> lps(mesh.points);
  if (!o.lps)
    for (Vec3d& p : lps) p = {-p.x, -p.y, p.z};
  imaging::SampledMetric sampled =
      imaging::sampleMetricLogEuclidean(input.read.volume.geometry, built.metric, built.inDomain, lps);
  if (!sampled.outsideImage.empty() && !o.maskOutsideImage) {
    const VertexId v = static_cast<VertexId>(sampled.outsideImage.front());
    const Vec3d p = mesh.points[v];
    std::ostringstream s;
    s << o.tensors << ": " << sampled.outsideImage.size() << " mesh vertices lie outside the image, the first is "
      << mesh.fileNumber(v) << " at (" << p.x << ", " << p.y << ", " << p.z << ") " << (o.lps ? "LPS" : "RAS")
      << " (wrong --lps? use --outside-image mask to leave them out)";
    throw ToolError(kExitInput, s.str());
  }
  // The metric is LPS; a RAS mesh measures its edges in RAS: G_ras = F G F.
  if (!o.lps)
    for (SymTensor3& g : sampled.metric) g = imaging::changeTensorFrame(g, imaging::rasToLps());
  out.tensors = std::move(sampled.metric);
  out.inDomain = std::move(sampled.inDomain);
  out.alreadyMetric = true;
  out.description = o.tensors + " (" + imaging::metricFormula(o.tensor.metric.kind, o.tensor.metric.diffusionMetric) +
                    ", log-Euclidean trilinear at the vertices)";
  return out;
}

}  // namespace

std::string tetMeshOptionsHelp() {
  const OptionCommand mesh = kTetMeshDistanceCommand;
  return "Seeds (at least one; all are sources at distance 0):\n" + optionHelp(mesh, {OptionGroup::Seeds}) +
         "\n"
         "Metric (the Euclidean one when none is given):\n" +
         optionHelp(mesh, {OptionGroup::MeshMetric, OptionGroup::TensorFile, OptionGroup::Metric}) +
         "  Vertices whose tensor is unusable or below the FA threshold, and the tetrahedra touching\n"
         "  them, are left out (docs/cli.md).\n"
         "\n"
         "Propagation:\n" +
         optionHelp(mesh, {OptionGroup::Propagation}) +
         "\n"
         "Output:\n" +
         optionHelp(mesh, {OptionGroup::Output}) +
         "\n"
         "Exit codes: 0 success; 1 internal error; 2 bad command line; 3 unreadable or unusable\n"
         "mesh or tensors (bad counts, indices out of range, inverted or degenerate tetrahedra, a\n"
         "face of more than two tetrahedra);\n"
         "4 nothing to compute (seed out of range, outside the mesh or the domain); 5 output cannot\n"
         "be written; 6 not enough memory for the run (--no-memory-check runs anyway).\n";
}

bool isTetMeshInput(const std::string& input) {
  auto ends = [&](const char* suffix) {
    const std::size_t n = std::char_traits<char>::length(suffix);
    return input.size() > n && input.compare(input.size() - n, n, suffix) == 0;
  };
  return ends(".node") || ends(".ele");
}

int runTetMeshDistance(int argc, char** argv) {
  const Clock::time_point start = Clock::now();
  const TetDistanceOptions o = parseOptions(argc, argv);
  RunFiles files;
  files.inputTetMesh("mesh", o.input);
  if (o.tensors != "node" && o.tensors != "ele") files.inputImage("tensor image", o.tensors);
  files.inputImage("mask", o.tensor.maskPath);
  files.inputImage("reference image", o.reference);
  if (o.reference.empty())
    files.outputFile("distance output", o.output);
  else
    files.outputImage("distance output", o.output);
  files.check();

  const std::string base = tetmesh::tetGenBaseName(o.input);
  const std::string nodeFile = base + ".node", eleFile = base + ".ele";
  tetmesh::TetMesh mesh;
  try {
    mesh = tetmesh::readTetGenMesh(o.input);
  } catch (const tetmesh::TetMeshError& e) {
    throw ToolError(kExitInput, e.what());
  }

  // The grid of an image output, read before the work: from the
  // reference's header alone (its values are not used).
  imaging::ScalarImage reference;
  if (!o.reference.empty()) {
    try {
      reference.geometry = imaging::readImageGrid(o.reference, &reference.warnings);
    } catch (const imaging::ImageIoError& e) {
      throw ToolError(kExitInput, e.what());
    }
    noteInputWarnings(o.reference, reference.warnings);
  }

  // The metric per vertex and the vertices in the domain.
  VertexTensors vt;
  if (o.tensors == "node" || o.tensors == "ele") vt = tensorsFromAttributes(o, mesh, nodeFile, eleFile);
  else if (!o.tensors.empty()) vt = tensorsFromImage(o, mesh);
  std::vector<SymTensor3> metricTensors;
  std::vector<std::uint8_t> inDomain;
  if (vt.tensors.empty()) {
    metricTensors.assign(mesh.vertexCount(), SymTensor3{1.f, 0.f, 0.f, 1.f, 0.f, 1.f});
    inDomain.assign(mesh.vertexCount(), 1);
  } else if (vt.alreadyMetric) {
    metricTensors = std::move(vt.tensors);
    inDomain = std::move(vt.inDomain);
  } else {
    imaging::MetricFromTensors built = imaging::buildMetric(vt.tensors, {}, o.tensor.metric);
    metricTensors = std::move(built.metric);
    inDomain = std::move(built.inDomain);
  }

  // Tetrahedra with a corner outside the domain are left out; so are the
  // edges they alone contribute.
  tetmesh::TetrahedraInDomain kept = tetmesh::tetrahedraInDomain(mesh.tets, inDomain, o.input);
  std::vector<CellMeshDomain::Tetrahedron> tets = std::move(kept.tets);
  std::vector<std::uint8_t> inKeptTet = std::move(kept.covered);

  std::vector<VertexId> sources;
  for (long long n : o.seedVertices) {
    const long long v = n - mesh.firstIndex;
    if (v < 0 || v >= static_cast<long long>(mesh.vertexCount()))
      throw ToolError(kExitDomain, "--seed-vertex " + std::to_string(n) + ": out of range (vertices are numbered " +
                                       std::to_string(mesh.firstIndex) + ".." +
                                       std::to_string(mesh.fileNumber(static_cast<VertexId>(mesh.vertexCount() - 1))) +
                                       " in " + nodeFile + ")");
    if (!inKeptTet[v])
      throw ToolError(kExitDomain, "--seed-vertex " + std::to_string(n) + ": the vertex is outside the domain");
    sources.push_back(static_cast<VertexId>(v));
  }
  // The graph: the mesh's points, plus one vertex per seed point inserted
  // with --seed-at point (it splits its tetrahedron into four).
  std::vector<Vec3d> points = mesh.points;
  std::vector<std::uint8_t> inGraph = std::move(inKeptTet);
  for (const auto& s : o.seedPoints) {
    const Vec3d p{s[0], s[1], s[2]};
    std::ostringstream given;
    given << "--seed-point " << s[0] << "," << s[1] << "," << s[2];
    if (o.seedAtPoint) {
      std::array<double, 4> w{};
      const std::int64_t t = tetmesh::findContainingTet(points, tets, p, &w);
      if (t < 0) throw ToolError(kExitDomain, given.str() + ": the point lies in no tetrahedron of the domain");
      // The metric at p: the barycentric mean of the corners' metrics (a
      // convex combination of positive-definite tensors).
      const auto corners = tets[static_cast<std::size_t>(t)];
      double sum[6] = {0, 0, 0, 0, 0, 0}, total = 0.0;
      for (int c = 0; c < 4; ++c) {
        const double wc = std::max(0.0, w[c]);
        const SymTensor3& g = metricTensors[corners[c]];
        const double comps[6] = {g.xx, g.xy, g.xz, g.yy, g.yz, g.zz};
        for (int i = 0; i < 6; ++i) sum[i] += wc * comps[i];
        total += wc;
      }
      const VertexId added = static_cast<VertexId>(points.size());
      points.push_back(p);
      metricTensors.push_back({float(sum[0] / total), float(sum[1] / total), float(sum[2] / total),
                               float(sum[3] / total), float(sum[4] / total), float(sum[5] / total)});
      inGraph.push_back(1);
      for (int c = 0; c < 4; ++c) {
        auto split = corners;
        split[c] = added;
        if (c == 0) tets[static_cast<std::size_t>(t)] = split;
        else tets.push_back(split);
      }
      sources.push_back(added);
      continue;
    }
    if (tetmesh::findContainingTet(mesh, p) < 0)
      throw ToolError(kExitDomain, given.str() + ": the point lies in no tetrahedron of " + eleFile);
    const VertexId v = tetmesh::nearestVertex(mesh, p);
    if (!inGraph[v])
      throw ToolError(kExitDomain, given.str() + ": its nearest vertex " + std::to_string(mesh.fileNumber(v)) +
                                       " is outside the domain");
    sources.push_back(v);
  }
  std::sort(sources.begin(), sources.end());
  sources.erase(std::unique(sources.begin(), sources.end()), sources.end());

  {
    const std::uint64_t v = points.size(), t = tets.size();
    checkMemory(o.input, tetMeshRunMemoryEstimate(o, v, t),
                withThousands(v) + " vertices and " + withThousands(t) + " tetrahedra", !o.memoryCheck);
  }

  const double setupSeconds = secondsSince(start);
  const Clock::time_point propagationStart = Clock::now();
  // Messages about the tetrahedra (a face of more than two) name the file
  // that holds them.
  const tetmesh::TetMeshPropagation propagation = tetmesh::propagateOverTetrahedra(
      points, tets, metricTensors, inGraph, sources, o, o.maxDistance, eleFile);
  const double propagationSeconds = secondsSince(propagationStart);
  PropagationResult result = propagation.result;
  result.distance.resize(mesh.vertexCount());  // without points inserted for --seed-at point

  std::vector<double> values(result.distance.size());
  std::size_t reached = 0;
  double farthest = 0.0;
  for (std::size_t v = 0; v < values.size(); ++v) {
    if (std::isfinite(result.distance[v])) {
      values[v] = result.distance[v];
      ++reached;
      farthest = std::max(farthest, result.distance[v]);
    } else {
      values[v] = o.unreachableValue;
    }
  }
  tetmesh::TetMeshOutputFormat format;
  try {
    if (!o.reference.empty()) {
      const std::vector<double> resampled = tetmesh::resampleOntoGrid(
          mesh, result.distance, reference.geometry, o.lps ? tetmesh::MeshFrame::Lps : tetmesh::MeshFrame::Ras,
          o.unreachableValue);
      imaging::writeScalarImage(o.output, reference.geometry, std::vector<float>(resampled.begin(), resampled.end()));
    } else if (tetmesh::outputFormatOf(o.output, format)) {
      files::writeAtomically(o.output, [&](const std::string& staging) {
        tetmesh::writeTetMeshOutput(staging, format, mesh, {{"distance", std::move(values)}});
      });
    }
  } catch (const std::runtime_error& e) {  // files::OutputError, imaging::ImageIoError
    throw ToolError(kExitOutput, e.what());
  }

  if (!o.quiet) {
    std::ostringstream s;
    s << "Read " << nodeFile << ": " << withThousands(mesh.vertexCount()) << " vertices, "
      << withThousands(mesh.tets.size()) << " tetrahedra (" << withThousands(tets.size()) << " in the domain), "
      << withThousands(propagation.edgeCount) << " edges, numbered from " << mesh.firstIndex << ".\n"
      << "Metric: " << vt.description << ".\n"
      << (o.lanthier ? "Lanthier Steiner points, M = " + std::to_string(o.steinerPoints) + " per edge"
          : o.method == Method::Dijkstra ? std::string("Dijkstra")
                                       : "STVD k = " + std::to_string(memoryDepthOf<CellMeshDomain>(o)) + " (" +
                                             chainMeasureName(o.chainMeasure) + " measure)")
      << " from " << sources.size() << " seed vertex" << (sources.size() == 1 ? "" : "es") << ": reached "
      << withThousands(reached) << " of " << withThousands(mesh.vertexCount()) << " vertices, farthest "
      << fixed(farthest, 2) << "; " << withThousands(result.relaxedEdges)
      << (o.lanthier ? " segments measured in " : " edges relaxed in ")
      << fixed(propagationSeconds, 3) << " s (setup " << fixed(setupSeconds, 3) << " s)"
      << (o.lanthier || o.method == Method::Dijkstra
              ? std::string()
              : "; " + withThousands(result.measuredCandidates) + " candidates measured along their segments, " +
                    withThousands(result.refusedCandidates) + " refused (leaving the domain)")
      << ".\n"
      << "Wrote " << o.output << (o.reference.empty() ? "" : " on the grid of " + o.reference) << ".";
    std::cout << s.str() << std::endl;
  }
  return kExitOk;
}

}  // namespace stvd::tool
