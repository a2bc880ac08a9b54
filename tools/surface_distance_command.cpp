// `stvd distance MESH.(obj|off|ply) --seed-vertex N ...`: distances over a
// polygon surface (docs/surfaces.md). Reached from runDistance when the
// input is a surface mesh or --seed-vertex is given.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "geodesic_options.hpp"
#include "stvd/itk/atomic_output.hpp"
#include "stvd/itk/image_io_error.hpp"
#include "stvd/propagation.hpp"
#include "stvd/steiner_propagation.hpp"
#include "stvd/surface_domain.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"
#include "stvd/surface_metrics.hpp"
#include "surface_distance_command.hpp"

namespace stvd::tool {
namespace {

const char* kSurfaceDistanceHelp =
    "Usage: stvd distance MESH -o OUTPUT --seed-vertex N [options]\n"
    "\n"
    "Geodesic distance over a polygon surface (2-manifold, orientable; boundaries and several\n"
    "components allowed). MESH is .obj, .off or .ply (ASCII or binary; triangles or general\n"
    "polygons, used without triangulation). Distances are in the units of the mesh coordinates.\n"
    "\n"
    "Seeds (at least one):\n"
    "  --seed-vertex N         vertex index, counted from 0 in file order (repeatable).\n"
    "\n"
    "Metric:\n"
    "  --metric M              isotropic (default): surface distance;\n"
    "                          curvature: principal-curvature tensors, a unit step across the\n"
    "                          direction of larger curvature costs up to G (--anisotropy);\n"
    "                          field:FILE: one direction \"dx dy dz\" per vertex (world frame);\n"
    "                          a unit step along it costs 1, across it G (--anisotropy);\n"
    "                          tensors:FILE: one 3D tensor \"xx xy xz yy yz zz\" per vertex\n"
    "                          (world frame), projected to the tangent plane;\n"
    "                          face-tensors:FILE: the same per face (file order), averaged\n"
    "                          to the vertices by corner angle.\n"
    "  --anisotropy G          G >= 1 for curvature and field metrics (required for them).\n"
    "\n"
    "Propagation:\n"
    "  --method M              stvd (default), dijkstra, or lanthier: Steiner points on the face\n"
    "                          edges joined through each face, the slow accurate reference\n"
    "                          (needs --steiner; docs/steiner.md).\n"
    "  --steiner M             lanthier: Steiner points per face edge, 1..16; time grows like M^2,\n"
    "                          memory like M.\n"
    "  --k N                   STVD memory depth, 1..16 (default 8).\n"
    "  --chain-measure R       segment (default: real lines across the faces), projection\n"
    "                          (the paper's rule) or largest.\n"
    "\n"
    "Output:\n"
    "  -o, --output FILE       .ply (binary, the mesh with a double vertex property distance),\n"
    "                          .vtk (legacy POLYDATA, POINT_DATA distance; unreached -1) or\n"
    "                          .csv (rows vertex,distance; unreached inf). Written under a\n"
    "                          temporary name and renamed when complete.\n"
    "  -q, --quiet             no summary on stdout.\n"
    "  -h, --help              this text.\n";

/// --method, --steiner, --k and --chain-measure as in geodesic_options (no
/// --stencil), with the library's defaults.
struct SurfaceOptions : PropagationChoice {
  std::string input, output, metric = "isotropic";
  std::vector<long long> seeds;
  double anisotropy = 0.0;
  bool anisotropyGiven = false;
  bool quiet = false;
};

SurfaceOptions parse(int argc, char** argv) {
  SurfaceOptions o;
  ArgumentReader args(argc, argv, 2);
  while (!args.done()) {
    const std::string a = args.take();
    if (a == "-h" || a == "--help") {
      std::cout << kSurfaceDistanceHelp;
      throw ToolError(kExitOk, "");
    }
    if (!args.isOption(a)) {
      if (!o.input.empty()) usageError("more than one input: '" + o.input + "' and '" + a + "'");
      o.input = a;
    } else if (a == "-o" || a == "--output") {
      o.output = args.value(a);
    } else if (a == "--seed-vertex") {
      const std::string v = args.value(a);
      long long n = -1;
      try {
        std::size_t used = 0;
        n = std::stoll(v, &used);
        if (used != v.size()) n = -1;
      } catch (const std::exception&) {
        n = -1;
      }
      if (n < 0) usageError("--seed-vertex: '" + v + "' is not a vertex index (0, 1, 2, ...)");
      o.seeds.push_back(n);
    } else if (a == "--metric") {
      o.metric = args.value(a);
      if (o.metric != "isotropic" && o.metric != "curvature" && o.metric.rfind("field:", 0) != 0 &&
          o.metric.rfind("tensors:", 0) != 0 && o.metric.rfind("face-tensors:", 0) != 0)
        usageError("--metric: '" + o.metric +
                   "' is not one of isotropic, curvature, field:FILE, tensors:FILE, "
                   "face-tensors:FILE");
    } else if (a == "--anisotropy") {
      o.anisotropy = parseNumber(a, args.value(a));
      o.anisotropyGiven = true;
      if (!(o.anisotropy >= 1.0) || !std::isfinite(o.anisotropy))
        usageError("--anisotropy must be a number >= 1");
    } else if (a != "--stencil" && parsePropagationOption(a, args, o)) {
      // read into o's PropagationChoice
    } else if (a == "-q" || a == "--quiet") {
      args.noValue(a);
      o.quiet = true;
    } else {
      usageError("unknown option '" + a + "' for a surface (see stvd distance MESH --help)");
    }
  }
  if (o.input.empty()) usageError("no input mesh given");
  if (!surface_io::isSurfaceMeshPath(o.input))
    usageError(o.input + ": --seed-vertex needs a surface mesh input (.obj, .off or .ply)");
  if (o.output.empty()) usageError("no output given (-o FILE.ply, .vtk or .csv)");
  if (!surface_io::isSurfaceOutputPath(o.output))
    usageError(o.output + ": a surface distance is written as .ply, .vtk or .csv");
  if (o.seeds.empty()) usageError("no seed given (--seed-vertex N)");
  const bool needsGamma = o.metric == "curvature" || o.metric.rfind("field:", 0) == 0;
  if (needsGamma && !o.anisotropyGiven) usageError("--metric " + o.metric + " needs --anisotropy G");
  if (!needsGamma && o.anisotropyGiven)
    usageError("--anisotropy applies to the curvature and field metrics only");
  checkMeshPropagationChoice(o, "face edge", 4);
  return o;
}

RiemannianMetric buildMetric(const SurfaceOptions& o, const SurfaceDomain& surface) {
  if (o.metric == "isotropic") return isotropicSurfaceMetric(surface);
  if (o.metric == "curvature") return curvatureMetric(surface, o.anisotropy);
  const bool field = o.metric.rfind("field:", 0) == 0;
  const bool perFace = o.metric.rfind("face-tensors:", 0) == 0;
  const std::string file = o.metric.substr(o.metric.find(':') + 1);
  const auto table = surface_io::readVertexTable(file, field ? 3 : 6,
                                                 perFace ? surface.faceCount() : surface.vertexCount(),
                                                 perFace ? "face" : "vertex");
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

}  // namespace

bool isSurfaceDistanceCall(int argc, char** argv) {
  // A volume command never names a .obj/.off/.ply file (its inputs are
  // images, its outputs images or .vdb), so any such argument other than
  // the output marks a surface call; so does --seed-vertex.
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--seed-vertex" || a.rfind("--seed-vertex=", 0) == 0) return true;
    const std::string previous = argv[i - 1];
    if (!a.empty() && a[0] != '-' && previous != "-o" && previous != "--output" &&
        surface_io::isSurfaceMeshPath(a))
      return true;
  }
  return false;
}

int runSurfaceDistance(int argc, char** argv) {
  using Clock = std::chrono::steady_clock;
  const Clock::time_point start = Clock::now();
  SurfaceOptions o;
  try {
    o = parse(argc, argv);
  } catch (const ToolError& e) {
    if (e.exitCode() == kExitOk) return kExitOk;  // --help
    throw;
  }
  try {
    imaging::checkOutputPath(o.output);
  } catch (const imaging::ImageIoError& e) {
    throw ToolError(kExitOutput, e.what());
  }
  surface_io::SurfaceMesh mesh;
  std::optional<SurfaceDomain> surface;
  std::optional<RiemannianMetric> metric;
  try {
    mesh = surface_io::readSurfaceMesh(o.input);
    surface.emplace(mesh.points, mesh.faces);
    metric.emplace(buildMetric(o, *surface));
  } catch (const SurfaceError& e) {
    throw ToolError(kExitInput, o.input + ": " + e.what());
  } catch (const surface_io::MeshFileError& e) {
    throw ToolError(kExitInput, e.what());
  } catch (const std::invalid_argument& e) {
    throw ToolError(kExitInput, o.input + ": " + e.what());
  }
  std::vector<VertexId> sources;
  for (const long long s : o.seeds) {
    if (s >= static_cast<long long>(surface->vertexCount()))
      throw ToolError(kExitDomain, o.input + ": seed vertex " + std::to_string(s) +
                                       " does not exist (the mesh has " +
                                       std::to_string(surface->vertexCount()) + " vertices)");
    sources.push_back(static_cast<VertexId>(s));
  }
  PropagationResult result;
  if (o.lanthier) {
    SteinerOptions steiner;
    steiner.steinerPoints = o.steinerPoints;
    try {
      result = steinerPropagate(*surface, *metric, sources, steiner);
    } catch (const std::invalid_argument& e) {  // too large a graph for 32-bit point numbers
      throw ToolError(kExitUsage, o.input + ": --method lanthier: " + e.what());
    }
  } else {
    result = propagate(*surface, *metric, sources, propagationOptions(o));
  }

  try {
    imaging::AtomicOutput out(o.output);
    surface_io::writeSurfaceDistances(out.stagingPath(), o.output, mesh, result.distance);
    out.commit();
  } catch (const std::runtime_error& e) {
    throw ToolError(kExitOutput, e.what());
  }

  if (!o.quiet) {
    // Vertices not reached lie in components without a seed (or are isolated).
    std::vector<std::uint8_t> seeded(surface->componentCount(), 0);
    for (const VertexId s : sources) seeded[surface->component()[s]] = 1;
    std::size_t unreached = 0, otherComponents = 0;
    for (std::uint32_t c = 0; c < surface->componentCount(); ++c) otherComponents += seeded[c] ? 0 : 1;
    double farthest = 0.0;
    for (const double d : result.distance) {
      if (std::isfinite(d)) farthest = std::max(farthest, d);
      else ++unreached;
    }
    const double seconds = std::chrono::duration<double>(Clock::now() - start).count();
    std::cout << o.input << ": " << withThousands(surface->vertexCount()) << " vertices, "
              << withThousands(surface->faceCount()) << " faces, "
              << surface->componentCount() << " component(s); metric " << o.metric
              << (o.anisotropyGiven ? " (anisotropy " + fixed(o.anisotropy, 2) + ")" : "") << "; "
              << (o.lanthier ? "Lanthier M=" + std::to_string(o.steinerPoints)
                  : o.method == Method::Dijkstra ? std::string("Dijkstra")
                                                 : "STVD k=" + std::to_string(o.k))
              << ". Farthest reached distance " << fixed(farthest, 4) << "; "
              << withThousands(unreached) << " vertices unreachable"
              << (unreached ? " (in " + std::to_string(otherComponents) +
                                  " component(s) without a seed, isolated vertices included)"
                            : std::string())
              << ". Wrote " << o.output << " in " << fixed(seconds, 2) << " s." << std::endl;
  }
  return kExitOk;
}

}  // namespace stvd::tool
