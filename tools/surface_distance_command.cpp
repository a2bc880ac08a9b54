// `stvd distance MESH.(obj|off|ply) --seed-vertex N ...`: distances over a
// polygon surface (docs/surfaces.md). Reached from runDistance when the
// input is a surface mesh or --seed-vertex is given.
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <ctime>
#include <iomanip>
#include <iostream>
#include <limits>
#include <sstream>
#include <optional>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "command_options.hpp"
#include "geodesic_options.hpp"
#include "memory_check.hpp"
#include "tool_run_files.hpp"
#include "stvd/system/files/file_contents.hpp"
#include "stvd/system/files/output_transaction.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/front_end/region_connectivity_options.hpp"
#include "stvd/system/parallel_tasks.hpp"
#include "stvd/surface/manifold_sheets.hpp"
#include "stvd/surface/surface_region_distances.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "option_help.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/front_end/mesh_options.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "stvd/surface_io/cortical_surface_files.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"
#include "stvd/surface/surface_metrics.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/surface/surface_lanthier.hpp"
#include "stvd/front_end/memory_estimates.hpp"
#include "surface_distance_command.hpp"
#include "surface_seed_point.hpp"

namespace stvd::tool {
namespace {

const char* kSurfaceDistanceHelp =
    "Usage: stvd distance MESH -o OUTPUT --seed-vertex N|--seed-point X,Y,Z|--seeds FILE [options]\n"
    "\n"
    "Geodesic distance over a polygon surface (2-manifold, orientable; boundaries and several\n"
    "components allowed). MESH is .obj, .off, .ply (ASCII or binary; triangles or general\n"
    "polygons, used without triangulation), .stl (ASCII or binary; corners with the same\n"
    "coordinates are welded into one vertex, and the summary says how many), a GIfTI surface\n"
    "(.surf.gii) or a FreeSurfer surface (lh.pial, rh.white, ...; coordinates in tkr-RAS, the\n"
    "summary gives the transform to scanner RAS). Distances are in the units of the mesh\n"
    "coordinates (millimetres for GIfTI and FreeSurfer).\n";

/// The propagation's options with the library's defaults, and the
/// surface's own.
struct SurfaceOptions : PropagationChoice {
  std::string input, output, metric, statsPath;
  std::vector<long long> seeds;
  std::vector<std::array<double, 3>> seedPoints;
  std::string seedsFile, maskFile;
  /// Region mode (--region-matrix, --nearest-region): one propagation per
  /// region of --seeds.
  std::string regionMatrix, nearestRegion, regionMaps;
  unsigned threads = 0;
  bool regionMode() const { return !regionMatrix.empty() || !nearestRegion.empty() || !regionMaps.empty(); }
  std::vector<std::string> seedRegions;
  bool seedAtPoint = false;
  double anisotropy = 0.0;
  bool anisotropyGiven = false;
  double maxDistance = std::numeric_limits<double>::infinity();
  bool quiet = false;
};

SurfaceOptions parse(int argc, char** argv) {
  const CommandLine line = readCommandLine(kSurfaceDistanceCommand, argc, argv, 2, surfaceDistanceHelp);
  const OptionValues& v = line.values;
  SurfaceOptions o;
  static_cast<PropagationChoice&>(o) = propagationChoiceOf(v);
  o.input = line.input;
  o.output = v.text("--output").value_or("");
  for (const OptionValue& given : v.all("--seed-vertex")) {
    const long long n = std::get<long long>(given);
    if (n < 0) usageError("--seed-vertex: '" + std::to_string(n) + "' is not a vertex index (0, 1, 2, ...)");
    o.seeds.push_back(n);
  }
  o.seedPoints = imaging::pointsOf(v, "--seed-point");
  o.seedAtPoint = v.text("--seed-at") == "point";
  o.seedsFile = v.text("--seeds").value_or("");
  o.maskFile = v.text("--mask").value_or("");
  o.regionMatrix = v.text("--region-matrix").value_or("");
  o.nearestRegion = v.text("--nearest-region").value_or("");
  o.regionMaps = v.text("--region-maps").value_or("");
  o.threads = regionThreadsOf(v);
  for (const OptionValue& given : v.all("--seed-region")) o.seedRegions.push_back(std::get<std::string>(given));
  o.maxDistance = v.number("--max-distance").value_or(o.maxDistance);
  o.statsPath = v.text("--stats").value_or("");
  o.metric = v.text("--metric").value_or(optionDefaultText(toolOption("--metric"), kSurfaceDistanceCommand));
  o.anisotropyGiven = v.has("--anisotropy");
  o.anisotropy = v.number("--anisotropy").value_or(0.0);
  o.quiet = v.has("--quiet");
  if (o.input.empty()) usageError("no input mesh given");
  if (!surface_io::isSurfaceMeshPath(o.input) && !surface_io::isFreeSurferSurfaceFile(o.input))
    usageError(o.input + ": --seed-vertex needs a surface mesh input (.obj, .off, .ply, .stl, .surf.gii or a "
                         "FreeSurfer surface)");
  if (o.output.empty()) usageError("no output given (-o FILE.ply, .vtk, .csv, .shape.gii, .func.gii or .curv)");
  if (!surface_io::isSurfaceOutputPath(o.output))
    usageError(o.output + ": a surface distance is written as .ply, .vtk, .csv, .shape.gii, .func.gii or a "
                          "FreeSurfer curv file (.curv, lh.NAME, rh.NAME)");
  if (o.seeds.empty() && o.seedPoints.empty() && o.seedsFile.empty())
    usageError("no seed given (--seed-vertex N, --seed-point X,Y,Z or --seeds FILE)");
  const bool namedRegions = !o.seedsFile.empty() && surface_io::isVertexRegionsPath(o.seedsFile) &&
                            o.seedsFile.size() > 6 && o.seedsFile.compare(o.seedsFile.size() - 6, 6, ".label") != 0;
  if (!o.seedRegions.empty() && !namedRegions)
    usageError("--seed-region selects regions of a --seeds annotation (.annot) or GIfTI label file (.label.gii)");
  if (namedRegions && o.seedRegions.empty() && !o.regionMode())
    usageError(o.seedsFile + ": name the seed regions with --seed-region NAME");
  if (o.regionMode()) {
    if (o.seedsFile.empty() || !surface_io::isVertexRegionsPath(o.seedsFile))
      usageError("--region-matrix, --region-maps and --nearest-region need --seeds REGIONS (.annot, .label.gii or "
                 ".label)");
    if (!o.seeds.empty() || !o.seedPoints.empty())
      usageError("--region-matrix, --region-maps and --nearest-region measure from the regions of --seeds, not "
                 "from --seed-vertex or --seed-point");
    if (o.lanthier) usageError("--region-matrix, --region-maps and --nearest-region run with --method stvd or dijkstra");
    if (!o.regionMaps.empty() &&
        (o.regionMaps.find("{region}") == std::string::npos ||
         surface_io::vertexValuesFormatOf(o.regionMaps) == surface_io::VertexValuesFormat::None))
      usageError(o.regionMaps + ": --region-maps takes a pattern with {region} ending in .shape.gii, .func.gii or "
                 ".curv (or lh.{region}...)");
    if (!o.nearestRegion.empty() &&
        surface_io::vertexValuesFormatOf(o.nearestRegion) == surface_io::VertexValuesFormat::None)
      usageError(o.nearestRegion + ": --nearest-region is written as .shape.gii, .func.gii or FreeSurfer curv");
  }
  if (v.has("--threads") && !o.regionMode())
    usageError("--threads applies to --region-matrix, --region-maps and --nearest-region");
  if (!o.seedsFile.empty() && !surface_io::isVertexRegionsPath(o.seedsFile) &&
      !surface_io::isVertexValuesPath(o.seedsFile))
    usageError(o.seedsFile + ": --seeds takes a .label, .annot, .label.gii, .func.gii, .shape.gii, .mgh, .mgz or "
                             "curv file");
  if (!o.maskFile.empty() && !surface_io::isVertexRegionsPath(o.maskFile) &&
      !surface_io::isVertexValuesPath(o.maskFile))
    usageError(o.maskFile + ": --mask takes a .func.gii, .shape.gii, .label.gii, .label, .mgh, .mgz or curv file");
  if (o.seedAtPoint && o.seedPoints.empty()) usageError("--seed-at applies to --seed-point");
  checkSurfaceMetricChoice(o.metric, o.anisotropyGiven, OptionNaming::Flags);
  checkMeshPropagationChoice(o, "face edge", 4);
  return o;
}

/// The seeds as vertices of the mesh the propagation runs on, with the
/// points inserted by --seed-at point.
struct SurfaceSeeds {
  /// The seeds given one by one first (givenAs holds their description),
  /// then those of --seeds.
  std::vector<VertexId> vertices;
  std::vector<std::string> givenAs;  // for the summary and --stats
  /// --seeds: the file's seed vertices, by region (or one entry).
  std::vector<std::pair<std::string, std::size_t>> fromFile;
  /// Region mode: the regions (their vertices, names and keys).
  std::vector<std::vector<VertexId>> regions;
  std::vector<std::string> regionNames;
  std::vector<std::int32_t> regionKeys;
  /// --mask: the faces kept and left out.
  std::size_t maskedOutFaces = 0, maskVertices = 0;
  /// Per inserted vertex (in order), the vertices it interpolates.
  std::vector<std::vector<std::pair<VertexId, double>>> inserted;
  /// For each face of the mesh, the face of the file it comes from.
  std::vector<std::size_t> faceOrigin;
};

/// Per vertex, whether a --seeds or --mask file marks it: a region file's
/// vertices in any region other than 0, or a non-zero value.
std::vector<std::uint8_t> markedVertices(const std::string& path, std::size_t vertexCount) {
  std::vector<std::uint8_t> marked(vertexCount, 0);
  if (surface_io::isVertexRegionsPath(path)) {
    const surface_io::VertexRegions regions = surface_io::readVertexRegions(path, vertexCount);
    for (std::size_t v = 0; v < vertexCount; ++v)
      marked[v] = regions.key[v] != surface_io::VertexRegions::kNoRegion && regions.key[v] != 0;
  } else {
    const std::vector<double> values = surface_io::readVertexValues(path, vertexCount);
    for (std::size_t v = 0; v < vertexCount; ++v) {
      if (std::isnan(values[v])) throw surface_io::MeshFileError(path + ": vertex " + std::to_string(v) + " is NaN");
      marked[v] = values[v] != 0.0;
    }
  }
  return marked;
}

SurfaceSeeds resolveSeeds(const SurfaceOptions& o, surface_io::SurfaceMesh& mesh) {
  SurfaceSeeds seeds;
  const std::size_t fileVertices = mesh.points.size();
  if (!o.maskFile.empty()) {
    // Only the faces with every corner inside: the paths stay on them.
    const std::vector<std::uint8_t> inside = markedVertices(o.maskFile, fileVertices);
    PolygonList kept;
    for (std::size_t f = 0; f < mesh.faces.faceCount(); ++f) {
      const auto b = mesh.faces.faceVertex.begin() + mesh.faces.faceStart[f];
      const auto e = mesh.faces.faceVertex.begin() + mesh.faces.faceStart[f + 1];
      if (std::all_of(b, e, [&](VertexId v) { return inside[v] != 0; })) {
        kept.add(b, e);
        seeds.faceOrigin.push_back(f);
      }
    }
    seeds.maskedOutFaces = mesh.faces.faceCount() - kept.faceCount();
    seeds.maskVertices = static_cast<std::size_t>(std::count(inside.begin(), inside.end(), 1));
    if (kept.faceCount() == 0)
      throw ToolError(kExitDomain, o.maskFile + ": no face has all its corners inside the mask");
    mesh.faces = std::move(kept);
  } else {
    seeds.faceOrigin.resize(mesh.faces.faceCount());
    for (std::size_t f = 0; f < seeds.faceOrigin.size(); ++f) seeds.faceOrigin[f] = f;
  }
  for (const long long s : o.seeds) {
    if (s >= static_cast<long long>(fileVertices))
      throw ToolError(kExitDomain, o.input + ": seed vertex " + std::to_string(s) + " does not exist (the mesh has " +
                                       std::to_string(fileVertices) + " vertices)");
    seeds.vertices.push_back(static_cast<VertexId>(s));
    seeds.givenAs.push_back("vertex " + std::to_string(s));
  }
  for (const auto& given : o.seedPoints) {
    const Vec3d point{given[0], given[1], given[2]};
    const std::string text = "point " + pointText(point, 4);
    if (!o.seedAtPoint) {
      const VertexId v = nearestVertex(mesh, point);
      seeds.vertices.push_back(v);
      seeds.givenAs.push_back(text + ": nearest vertex " + std::to_string(v) + " at distance " +
                              fixed(norm(mesh.points[v] - point), 4));
      continue;
    }
    const SurfacePoint closest = closestSurfacePoint(mesh, point);
    const std::size_t face = seeds.faceOrigin[closest.face], before = mesh.points.size();
    const VertexId v = insertSurfacePoint(mesh, closest, seeds.faceOrigin);
    if (mesh.points.size() > before) seeds.inserted.push_back(closest.weights);
    seeds.vertices.push_back(v);
    seeds.givenAs.push_back(text + ": " +
                            (mesh.points.size() > before
                                 ? std::string(closest.weights.size() == 2 ? "on an edge" : "inside") +
                                       " of face " + std::to_string(face) + ", inserted as vertex " +
                                       std::to_string(v)
                                 : "on vertex " + std::to_string(v)) +
                            " at distance " + fixed(closest.distance, 4) + " from the point");
  }
  if (o.regionMode()) {
    // Each region apart: those named, else every named region with vertices.
    const surface_io::VertexRegions regions = surface_io::readVertexRegions(o.seedsFile, fileVertices);
    std::vector<std::string> names = o.seedRegions;
    if (names.empty())
      for (const auto& [key, name] : regions.name)
        if (std::count(regions.key.begin(), regions.key.end(), key) > 0) names.push_back(name);
    if (names.empty()) throw ToolError(kExitDomain, o.seedsFile + ": no region has a vertex");
    for (const std::string& name : names) {
      try {
        seeds.regions.push_back(surface_io::regionVertices(regions, name, o.seedsFile));
      } catch (const surface_io::MeshFileError& e) {
        throw ToolError(kExitDomain, e.what());
      }
      for (const auto& [key, n] : regions.name)
        if (n == name) seeds.regionKeys.push_back(key);
      seeds.regionNames.push_back(name);
      seeds.fromFile.emplace_back(name, seeds.regions.back().size());
      seeds.vertices.insert(seeds.vertices.end(), seeds.regions.back().begin(), seeds.regions.back().end());
    }
  } else if (!o.seedsFile.empty()) {
    if (o.seedRegions.empty()) {
      const std::vector<std::uint8_t> marked = markedVertices(o.seedsFile, fileVertices);
      std::size_t count = 0;
      for (std::size_t v = 0; v < fileVertices; ++v)
        if (marked[v]) {
          seeds.vertices.push_back(static_cast<VertexId>(v));
          ++count;
        }
      if (count == 0) throw ToolError(kExitDomain, o.seedsFile + ": no seed vertex (no vertex is marked)");
      seeds.fromFile.emplace_back("", count);
    } else {
      const surface_io::VertexRegions regions = surface_io::readVertexRegions(o.seedsFile, fileVertices);
      for (const std::string& name : o.seedRegions) {
        std::vector<VertexId> vertices;
        try {
          vertices = surface_io::regionVertices(regions, name, o.seedsFile);
        } catch (const surface_io::MeshFileError& e) {
          throw ToolError(kExitDomain, e.what());
        }
        seeds.vertices.insert(seeds.vertices.end(), vertices.begin(), vertices.end());
        seeds.fromFile.emplace_back(name, vertices.size());
      }
    }
  }
  if (!o.maskFile.empty()) {
    // A seed off every kept face would seed nothing but itself.
    std::vector<std::uint8_t> used(mesh.points.size(), 0);
    for (const VertexId v : mesh.faces.faceVertex) used[v] = 1;
    for (const VertexId v : seeds.vertices)
      if (!used[v])
        throw ToolError(kExitDomain, o.maskFile + ": seed vertex " + std::to_string(v) +
                                         " is outside the mask (on no face whose corners are all inside)");
  }
  return seeds;
}

RiemannianMetric buildMetric(const SurfaceOptions& o, const SurfaceDomain& surface, const SurfaceSeeds& seeds,
                             const ManifoldSheets& sheets) {
  if (o.metric == "isotropic") return isotropicSurfaceMetric(surface);
  if (o.metric == "curvature") return curvatureMetric(surface, o.anisotropy);
  const bool field = o.metric.rfind("field:", 0) == 0;
  const bool perFace = o.metric.rfind("face-tensors:", 0) == 0;
  const std::string file = o.metric.substr(o.metric.find(':') + 1);
  // The file has a row per vertex or face of the file's mesh.
  const std::size_t fileRows =
      perFace ? *std::max_element(seeds.faceOrigin.begin(), seeds.faceOrigin.end()) + 1
              : sheets.inputVertexCount - seeds.inserted.size();
  const bool scale = o.metric.rfind("scale:", 0) == 0;
  std::vector<std::vector<double>> table;
  if (scale) {
    // A step near a vertex costs `s` times its length: the tensor s² I.
    std::vector<double> values;
    if (surface_io::isVertexValuesPath(file)) {
      values = surface_io::readVertexValues(file, fileRows);
    } else {
      for (const auto& row : surface_io::readVertexTable(file, 1, fileRows)) values.push_back(row[0]);
    }
    for (std::size_t v = 0; v < values.size(); ++v) {
      const double x = values[v];
      if (!(x > 0.0) || !std::isfinite(x))
        throw surface_io::MeshFileError(file + ": vertex " + std::to_string(v) + ": the scale " + std::to_string(x) +
                                        " is not a positive number");
      table.push_back({x * x, 0.0, 0.0, x * x, 0.0, x * x});
    }
  } else {
    table = surface_io::readVertexTable(file, field ? 3 : 6, fileRows, perFace ? "face" : "vertex");
  }
  if (perFace) {
    std::vector<std::vector<double>> perMeshFace;
    for (const std::size_t origin : seeds.faceOrigin) perMeshFace.push_back(table[origin]);
    table.swap(perMeshFace);
  } else {
    // Inserted vertices: the barycentric mean of their corners' rows;
    // directions first turned to agree in sign with the first corner's.
    for (const auto& weights : seeds.inserted) {
      std::vector<double> row(table[0].size(), 0.0);
      const std::vector<double>& reference = table[weights.front().first];
      for (const auto& [v, w] : weights) {
        double sign = 1.0;
        if (field) {
          double d = 0.0;
          for (int c = 0; c < 3; ++c) d += table[v][c] * reference[c];
          sign = d < 0.0 ? -1.0 : 1.0;
        }
        for (std::size_t c = 0; c < row.size(); ++c) row[c] += w * sign * table[v][c];
      }
      table.push_back(row);
    }
    // The copies made by splitting a non-manifold mesh: their vertex's row.
    for (std::size_t v = sheets.inputVertexCount; v < sheets.original.size(); ++v)
      table.push_back(table[sheets.original[v]]);
  }
  if (field) {
    std::vector<Vec3d> directions;
    for (const auto& r : table) directions.push_back({r[0], r[1], r[2]});
    return vectorFieldMetric(surface, directions, 1.0, o.anisotropy);
  }
  std::vector<SymTensor3> tensors;
  for (const auto& r : table)
    tensors.push_back({float(r[0]), float(r[1]), float(r[2]), float(r[3]), float(r[4]), float(r[5])});
  try {
    return perFace ? surfaceMetricFromFaceTensors(surface, tensors)
                   : surfaceMetricFromWorldTensors(surface, tensors);
  } catch (const std::invalid_argument& e) {
    throw surface_io::MeshFileError(file + ": " + e.what());
  }
}

/// One --region-maps file name: {region} replaced by the region's name,
/// with characters outside [A-Za-z0-9._-] replaced by '_' (no folder, no
/// hidden file from a name).
std::string regionMapPath(const std::string& pattern, std::string name) {
  for (char& c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_' && c != '.') c = '_';
  if (name.empty() || name[0] == '.') name = "_" + name;
  std::string path = pattern;
  for (std::size_t at; (at = path.find("{region}")) != std::string::npos;) path.replace(at, 8, name);
  return path;
}

/// The region matrix as CSV, as `stvd connectivity --matrix` writes it:
/// '#' header lines (the region names in order), then row a, column b.
std::string regionMatrixCsv(const SurfaceSeeds& seeds, const SurfaceRegionDistances& r) {
  const std::size_t n = seeds.regionNames.size();
  std::ostringstream csv;
  csv << "# stvd distance --region-matrix: geodesic distance from the region of the row to the nearest vertex of "
         "the region of the column\n# labels: ";
  for (std::size_t a = 0; a < n; ++a) {
    std::string name = seeds.regionNames[a];
    for (char& c : name)
      if (c == ',' || c == '\n' || c == '\r') c = ' ';
    csv << (a ? "," : "") << name;
  }
  csv << "\n" << std::setprecision(9);
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = 0; b < n; ++b) {
      const double d = r.matrix[a * n + b];
      csv << (b ? "," : "");
      if (std::isfinite(d)) csv << d;
      else csv << "inf";
    }
    csv << "\n";
  }
  return csv.str();
}

std::string methodName(const SurfaceOptions& o) {
  return o.lanthier ? "Lanthier M=" + std::to_string(o.steinerPoints)
         : o.method == Method::Dijkstra ? std::string("Dijkstra")
                                        : "STVD k=" + std::to_string(memoryDepthOf<SurfaceDomain>(o));
}

/// What --stats reports besides the options and the file's mesh.
struct SurfaceRun {
  std::size_t components = 0;
  const SurfaceSeeds* seeds = nullptr;
  const ManifoldSheets* sheets = nullptr;
  int propagations = 1;
  const PropagationResult* result = nullptr;
  std::vector<double> distance;  // the file's vertices
  double read = 0, metric = 0, propagate = 0, write = 0, total = 0;
  /// The same phases in processor seconds of the process (all threads,
  /// std::clock): on a shared machine the wall clock measures the load.
  double cpuRead = 0, cpuMetric = 0, cpuPropagate = 0;
  MemoryCheck memory;
};

std::string surfaceStatsJson(const SurfaceOptions& o, const surface_io::SurfaceMesh& file, const SurfaceRun& run) {
  std::vector<double> reached;
  for (const double d : run.distance)
    if (std::isfinite(d)) reached.push_back(d);
  std::sort(reached.begin(), reached.end());
  std::ostringstream j;
  j << "{\n  \"input\": " << jsonString(o.input) << ",\n  \"output\": " << jsonString(o.output) << ",\n";
  j << "  \"parameters\": {\"method\": "
    << jsonString(o.lanthier ? "lanthier" : o.method == Method::Dijkstra ? "dijkstra" : "stvd")
    << ", \"k\": " << (o.lanthier ? std::string("null") : std::to_string(memoryDepthOf<SurfaceDomain>(o)))
    << ", \"chain_measure\": "
    << (o.lanthier ? std::string("null")
                   : jsonString(chainMeasureName(o.chainMeasure)))
    << ", \"steiner_points\": " << (o.lanthier ? std::to_string(o.steinerPoints) : std::string("null"))
    << ", \"metric\": " << jsonString(o.metric)
    << ", \"anisotropy\": " << (o.anisotropyGiven ? jsonNumber(o.anisotropy) : std::string("null"))
    << ", \"max_distance\": " << jsonNumber(o.maxDistance)
    << ", \"seed_at\": " << jsonString(o.seedAtPoint ? "point" : "vertex") << "},\n";
  j << "  \"mesh\": {\"vertices\": " << file.points.size() << ", \"faces\": " << file.faces.faceCount()
    << ", \"components\": " << run.components << ", \"welded_vertices\": " << file.weldedVertices
    << ", \"degenerate_facets\": " << file.degenerateFacets
    << ", \"coordinate_type\": " << jsonString(surface_io::plyTypeName(file.coordinateType))
    << ", \"inserted_vertices\": " << run.seeds->inserted.size() << ", \"format\": " << jsonString(file.format)
    << ", \"anatomical_structure\": " << jsonString(file.anatomicalStructure)
    << ", \"coordinate_space\": " << jsonString(file.coordinates.space) << ", \"transformed_space\": "
    << (file.coordinates.hasTransform ? jsonString(file.coordinates.transformedSpace) : std::string("null"))
    << ", \"transform\": ";
  if (file.coordinates.hasTransform) {
    j << "[";
    for (int i = 0; i < 16; ++i) j << (i ? ", " : "") << jsonNumber(file.coordinates.transform[i]);
    j << "]";
  } else {
    j << "null";
  }
  j << ", \"mask\": " << (o.maskFile.empty() ? std::string("null")
                                               : "{\"file\": " + jsonString(o.maskFile) + ", \"vertices_inside\": " +
                                                     std::to_string(run.seeds->maskVertices) +
                                                     ", \"faces_left_out\": " +
                                                     std::to_string(run.seeds->maskedOutFaces) + "}")
    << "},\n";
  j << "  \"seed_file\": ";
  if (o.seedsFile.empty()) {
    j << "null,\n";
  } else {
    j << "{\"file\": " << jsonString(o.seedsFile) << ", \"regions\": [";
    for (std::size_t r = 0; r < run.seeds->fromFile.size(); ++r)
      j << (r ? ", " : "") << "{\"name\": " << jsonString(run.seeds->fromFile[r].first)
        << ", \"vertices\": " << run.seeds->fromFile[r].second << "}";
    j << "]},\n";
  }
  j << "  \"seeds\": [";
  for (std::size_t s = 0; s < run.seeds->givenAs.size(); ++s)
    j << (s ? ", " : "") << "{\"vertex\": " << run.seeds->vertices[s]
      << ", \"given_as\": " << jsonString(run.seeds->givenAs[s]) << "}";
  j << "],\n";
  j << "  \"distance\": {\"reached\": " << reached.size() << ", \"unreached\": "
    << run.distance.size() - reached.size() << ", \"min\": "
    << (reached.empty() ? "null" : jsonNumber(reached.front()))
    << ", \"median\": " << (reached.empty() ? "null" : jsonNumber(reached[reached.size() / 2]))
    << ", \"max\": " << (reached.empty() ? "null" : jsonNumber(reached.back())) << "},\n";
  j << "  \"non_manifold\": {\"edges_with_more_than_two_faces\": " << run.sheets->nonManifoldEdges
    << ", \"faces_cut_off_at_them\": " << run.sheets->detachedFaces
    << ", \"vertices_split\": " << run.sheets->splitVertices
    << ", \"vertex_copies_added\": " << run.sheets->addedVertices
    << ", \"propagations\": " << run.propagations << "},\n";
  j << "  \"propagation\": {\"finalized_vertices\": " << run.result->finalizedVertices
    << ", \"relaxed_edges\": " << run.result->relaxedEdges << "},\n";
  j << "  \"seconds\": {\"read\": " << jsonNumber(run.read) << ", \"metric\": " << jsonNumber(run.metric)
    << ", \"propagate\": " << jsonNumber(run.propagate) << ", \"write\": " << jsonNumber(run.write)
    << ", \"total\": " << jsonNumber(run.total) << "},\n";
  j << "  \"cpu_seconds\": {\"read\": " << jsonNumber(run.cpuRead) << ", \"metric\": " << jsonNumber(run.cpuMetric)
    << ", \"propagate\": " << jsonNumber(run.cpuPropagate) << "},\n";
  j << "  \"memory\": " << memoryCheckJson(run.memory) << ",\n";
  j << "  \"peak_memory_bytes\": " << peakMemoryBytes() << "\n}\n";
  return j.str();
}

}  // namespace

std::string surfaceDistanceHelp() { return kSurfaceDistanceHelp + ("\n" + surfaceOptionsHelp()); }

std::string surfaceOptionsHelp() {
  const OptionCommand surface = kSurfaceDistanceCommand;
  return "Seeds (at least one):\n" + optionHelp(surface, {OptionGroup::Seeds}) +
         "\n"
         "Metric:\n" +
         optionHelp(surface, {OptionGroup::SurfaceMetric}) +
         "\n"
         "Domain:\n" +
         optionHelp(surface, {OptionGroup::TensorFile}) +
         "\n"
         "Propagation:\n" +
         optionHelp(surface, {OptionGroup::Propagation}) +
         "\n"
         "Output:\n" +
         optionHelp(surface, {OptionGroup::Output}) +
         "\n"
         "Exit codes: 0 success; 1 internal error; 2 bad command line; 3 unreadable or unusable mesh or\n"
         "metric file; 4 a seed vertex that does not exist; 5 output cannot be written; 6 not enough\n"
         "memory for the run.\n";
}

bool isSurfaceDistanceCall(int argc, char** argv) {
  // A volume command never names a .obj/.off/.ply/.stl file (its inputs are
  // images, its outputs images or .vdb), so any such argument other than
  // the output marks a surface call; so does --seed-vertex.
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seed-vertex" || a.rfind("--seed-vertex=", 0) == 0) return true;
    const std::string previous = argv[i - 1];
    if (!a.empty() && a[0] != '-' && previous != "-o" && previous != "--output" &&
        (surface_io::isSurfaceMeshPath(a) || surface_io::isFreeSurferSurfaceFile(a)))
      return true;
  }
  return false;
}

int runSurfaceDistance(int argc, char** argv) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  const auto since = [](Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); };
  const auto cpuSince = [](std::clock_t t) { return double(std::clock() - t) / CLOCKS_PER_SEC; };
  SurfaceOptions o;
  try {
    o = parse(argc, argv);
  } catch (const ToolError& e) {
    if (e.exitCode() == kExitOk) return kExitOk;  // --help
    throw;
  }
  // The run's files, checked before anything is read; the --region-maps
  // files once the regions' names are known (checked again with them).
  auto runFiles = [&o](const std::vector<std::string>& maps) {
    RunFiles files;
    files.inputFile("surface mesh", o.input);
    if (o.metric.find(':') != std::string::npos)
      files.inputFile("metric file", o.metric.substr(o.metric.find(':') + 1));
    if (!o.seedsFile.empty()) files.inputFile("seed file", o.seedsFile);
    if (!o.maskFile.empty()) files.inputFile("mask", o.maskFile);
    files.outputFile("distance output", o.output);
    files.outputFile("statistics file", o.statsPath);
    files.outputFile("region matrix", o.regionMatrix);
    files.outputFile("nearest-region map", o.nearestRegion);
    for (const std::string& map : maps) files.outputFile("region map", map);
    files.check();
  };
  runFiles({});
  SurfaceRun run;
  Clock::time_point phase = Clock::now();
  std::clock_t cpuPhase = std::clock();
  surface_io::SurfaceMesh file, mesh;
  std::optional<SurfaceDomain> surface;
  std::optional<RiemannianMetric> metric;
  SurfaceSeeds seeds;
  ManifoldSheets sheets;
  try {
    file = surface_io::readSurfaceMesh(o.input);
    mesh = file;
    seeds = resolveSeeds(o, mesh);
    run.read = since(phase);
    run.cpuRead = cpuSince(cpuPhase);
    phase = Clock::now();
    cpuPhase = std::clock();
    // Non-manifold edges and vertices are split into manifold sheets, which
    // the propagation joins again at the split vertices.
    surface.emplace(surfaceOfSheets(mesh.points, mesh.faces, sheets));
    metric.emplace(buildMetric(o, *surface, seeds, sheets));
  } catch (const SurfaceError& e) {
    throw ToolError(kExitInput, o.input + ": " + e.what());
  } catch (const surface_io::MeshFileError& e) {
    throw ToolError(kExitInput, e.what());
  } catch (const std::invalid_argument& e) {
    throw ToolError(kExitInput, o.input + ": " + e.what());
  }
  run.metric = since(phase);
  run.cpuMetric = cpuSince(cpuPhase);
  std::vector<std::string> regionMaps;
  for (const std::string& name : seeds.regionNames)
    if (!o.regionMaps.empty()) regionMaps.push_back(regionMapPath(o.regionMaps, name));
  if (!regionMaps.empty()) runFiles(regionMaps);
  std::vector<VertexId> sources;
  for (const VertexId v : seeds.vertices) {
    if (!sheets.changed()) {
      sources.push_back(v);
      continue;
    }
    for (const VertexId c : sheets.copiesOf(v)) sources.push_back(c);
  }
  std::sort(sources.begin(), sources.end());
  sources.erase(std::unique(sources.begin(), sources.end()), sources.end());
  {
    // Region mode: one propagation at a time on each thread, and with
    // --region-maps every region's map kept until it is written.
    const std::uint64_t v = surface->vertexCount();
    const unsigned threadCount = o.regionMode() ? threadCountFor(o.threads, seeds.regions.size()) : 1;
    const std::uint64_t maps = regionMaps.size() * std::uint64_t{file.points.size()} * sizeof(double);
    run.memory = checkMemory(
        o.input, threadCount * surfaceRunMemoryEstimate(o, v, mesh.faces.faceVertex.size()) + maps,
        (threadCount > 1 ? std::to_string(threadCount) + " propagations at once on " : std::string()) +
            withThousands(v) + " vertices",
        !o.memoryCheck);
  }

  phase = Clock::now();
  cpuPhase = std::clock();
  PropagationResult result;
  SurfaceRegionDistances regionResult;
  if (o.lanthier && sheets.changed())
    throw ToolError(kExitUsage, o.input + ": --method lanthier does not run on a non-manifold mesh (" +
                                    std::to_string(sheets.nonManifoldEdges) + " edges shared by more than two faces, " +
                                    std::to_string(sheets.splitVertices) +
                                    " vertices split into sheets); use --method stvd or dijkstra");
  if (o.lanthier) {
    LanthierOptions steiner;
    steiner.steinerPoints = o.steinerPoints;
    steiner.maxDistance = o.maxDistance;
    try {
      result = lanthierPropagate(*surface, *metric, sources, steiner);
    } catch (const std::invalid_argument& e) {  // too large a graph for 32-bit point numbers
      throw ToolError(kExitUsage, o.input + ": --method lanthier: " + e.what());
    }
  } else if (o.regionMode()) {
    PropagationOptions options = propagationOptions(o);
    options.maxDistance = o.maxDistance;
    regionResult =
        surfaceRegionDistances(*surface, *metric, sheets, seeds.regions, options, o.threads, !regionMaps.empty());
    result.distance = regionResult.nearestDistance;
    for (const double d : result.distance) result.finalizedVertices += std::isfinite(d) ? 1 : 0;
  } else {
    PropagationOptions options = propagationOptions(o);
    options.maxDistance = o.maxDistance;
    result = propagateOverSheets(*surface, *metric, sheets, sources, options, &run.propagations);
  }
  run.propagate = since(phase);
  run.cpuPropagate = cpuSince(cpuPhase);
  // The outputs list the file's vertices: inserted seed points are left out.
  run.distance.assign(result.distance.begin(), result.distance.begin() + file.points.size());

  phase = Clock::now();
  // The distances and the statistics appear together or not at all.
  files::OutputTransaction outputs;
  try {
    outputs.write(o.output, [&](const std::string& staging) {
      surface_io::writeSurfaceDistances(staging, o.output, file, run.distance);
    });
    if (!o.regionMatrix.empty()) {
      const std::string csv = regionMatrixCsv(seeds, regionResult);
      outputs.write(o.regionMatrix, [&](const std::string& staging) { files::writeFileContents(staging, csv); });
    }
    for (std::size_t a = 0; a < regionMaps.size(); ++a) {
      std::vector<double>& map = regionResult.maps[a];
      map.resize(file.points.size());
      outputs.write(regionMaps[a], [&](const std::string& staging) {
        surface_io::writeSurfaceDistances(staging, regionMaps[a], file, map);
      });
    }
    if (!o.nearestRegion.empty()) {
      std::vector<double> keys(file.points.size(), -1.0);
      for (std::size_t v = 0; v < keys.size(); ++v)
        if (regionResult.nearestRegion[v] != SurfaceRegionDistances::kNoRegion)
          keys[v] = seeds.regionKeys[regionResult.nearestRegion[v]];
      outputs.write(o.nearestRegion, [&](const std::string& staging) {
        surface_io::writeVertexValues(staging, o.nearestRegion, file, keys, "nearest region");
      });
    }
    run.write = since(phase);
    run.total = since(start);
    run.seeds = &seeds;
    run.sheets = &sheets;
    run.result = &result;
    run.components = surface->componentCount();
    if (!o.statsPath.empty()) {
      const std::string json = surfaceStatsJson(o, file, run);
      outputs.write(o.statsPath, [&](const std::string& staging) { files::writeFileContents(staging, json); });
    }
    outputs.commit();
  } catch (const files::OutputError& e) {
    throw ToolError(kExitOutput, e.what());
  }

  if (!o.quiet) {
    // Vertices not reached lie in components without a seed (or are isolated)
    // or beyond --max-distance.
    std::vector<std::uint8_t> seeded(surface->componentCount(), 0);
    for (const VertexId s : sources) seeded[surface->component()[s]] = 1;
    std::size_t unreached = 0, otherComponents = 0;
    for (std::uint32_t c = 0; c < surface->componentCount(); ++c) otherComponents += seeded[c] ? 0 : 1;
    double farthest = 0.0;
    for (const double d : run.distance) {
      if (std::isfinite(d)) farthest = std::max(farthest, d);
      else ++unreached;
    }
    std::cout << o.input << ": " << withThousands(file.points.size()) << " vertices";
    if (file.weldedVertices)
      std::cout << " (" << withThousands(file.weldedVertices) << " duplicate facet corners welded"
                << (file.degenerateFacets ? ", " + withThousands(file.degenerateFacets) + " degenerate facets left out"
                                          : std::string())
                << ")";
    std::cout << ", " << withThousands(file.faces.faceCount()) << " faces, " << surface->componentCount()
              << " component(s); metric " << o.metric
              << (o.anisotropyGiven ? " (anisotropy " + fixed(o.anisotropy, 2) + ")" : "") << "; " << methodName(o);
    if (std::isfinite(o.maxDistance)) std::cout << ", stopping at " << fixed(o.maxDistance, 4);
    for (const std::string& s : seeds.givenAs)
      if (s.rfind("point", 0) == 0) std::cout << "; seed " << s;
    for (const auto& [region, count] : seeds.fromFile)
      std::cout << "; seeds: " << (region.empty() ? std::string() : "region " + region + " of ") << o.seedsFile
                << " (" << withThousands(count) << " vertices)";
    if (!o.maskFile.empty())
      std::cout << "; mask " << o.maskFile << ": " << withThousands(seeds.maskVertices) << " vertices inside, "
                << withThousands(seeds.maskedOutFaces) << " faces left out";
    if (!file.coordinates.space.empty()) {
      std::cout << "; coordinates in " << file.coordinates.space;
      if (file.coordinates.hasTransform) {
        const auto& t = file.coordinates.transform;
        const bool translation = t[0] == 1 && t[1] == 0 && t[2] == 0 && t[4] == 0 && t[5] == 1 && t[6] == 0 &&
                                 t[8] == 0 && t[9] == 0 && t[10] == 1;
        std::cout << " (" << file.coordinates.transformedSpace << " = "
                  << (translation ? "these + (" + fixed(t[3], 3) + ", " + fixed(t[7], 3) + ", " + fixed(t[11], 3) + ")"
                                  : std::string("the file's affine transform of these, in --stats"))
                  << ")";
      }
    }
    if (o.regionMode())
      std::cout << "; distances to the nearest of " << seeds.regions.size() << " region(s), one propagation each";
    if (sheets.changed())
      std::cout << "; non-manifold: " << withThousands(sheets.nonManifoldEdges)
                << " edge(s) shared by more than two faces (" << withThousands(sheets.detachedFaces)
                << " face(s) cut off there), " << withThousands(sheets.splitVertices)
                << " vertex(es) split into manifold sheets (" << withThousands(sheets.addedVertices)
                << " copies), joined again at those vertices (" << run.propagations << " propagations)";
    std::cout << ". Farthest reached distance " << fixed(farthest, 4) << "; " << withThousands(unreached)
              << " vertices unreachable";
    if (unreached && otherComponents)
      std::cout << " (in " << otherComponents << " component(s) without a seed, isolated vertices included"
                << (std::isfinite(o.maxDistance) ? ", or beyond the distance limit" : "") << ")";
    else if (unreached && std::isfinite(o.maxDistance))
      std::cout << " (beyond the distance limit)";
    std::cout << ". Wrote " << o.output << (o.regionMatrix.empty() ? "" : ", " + o.regionMatrix)
              << (regionMaps.empty() ? "" : ", " + std::to_string(regionMaps.size()) + " region maps")
              << (o.nearestRegion.empty() ? "" : ", " + o.nearestRegion)
              << (o.statsPath.empty() ? "" : " and " + o.statsPath) << " in "
              << fixed(run.total, 2) << " s." << std::endl;
  }
  return kExitOk;
}

}  // namespace stvd::tool
