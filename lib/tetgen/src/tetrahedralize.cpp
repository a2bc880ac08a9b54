// Our bridge to the TetGen library: surface input, validation, meshing.
#include "stvd/tetgen/tetrahedralize.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>
#include <string>
#include <tuple>
#include <vector>

#include <sys/stat.h>
#include <tetgen.h>

#include "stvd/system/files/regular_file.hpp"

namespace stvd::tetgen {
namespace {

using tetmesh::TetMeshError;

std::string lowerExtension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  if (dot == std::string::npos) return "";
  std::string e = path.substr(dot);
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e;
}

/// Points with identical coordinates become one (STL repeats the corners of
/// every triangle); polygons are renumbered accordingly.
SurfaceMesh mergeIdenticalPoints(const SurfaceMesh& s) {
  SurfaceMesh merged;
  std::map<std::tuple<double, double, double>, VertexId> index;
  std::vector<VertexId> newIndex(s.points.size());
  for (std::size_t v = 0; v < s.points.size(); ++v) {
    const Vec3d p = s.points[v];
    const auto key = std::make_tuple(p.x, p.y, p.z);
    const auto found = index.find(key);
    if (found != index.end()) {
      newIndex[v] = found->second;
    } else {
      newIndex[v] = static_cast<VertexId>(merged.points.size());
      index.emplace(key, newIndex[v]);
      merged.points.push_back(p);
    }
  }
  merged.polygons.reserve(s.polygons.size());
  for (const auto& polygon : s.polygons) {
    std::vector<VertexId> q;
    for (VertexId v : polygon) q.push_back(v < newIndex.size() ? newIndex[v] : v);
    merged.polygons.push_back(std::move(q));
  }
  return merged;
}

/// The volume a closed surface encloses (the divergence theorem over a fan
/// of triangles per polygon; either orientation).
double enclosedVolume(const SurfaceMesh& s) {
  double sixTimes = 0.0;
  for (const auto& polygon : s.polygons)
    for (std::size_t c = 1; c + 1 < polygon.size(); ++c) {
      const Vec3d a = s.points[polygon[0]], b = s.points[polygon[c]], d = s.points[polygon[c + 1]];
      const Vec3d n = cross(b, d);
      sixTimes += a.x * n.x + a.y * n.y + a.z * n.z;
    }
  return std::abs(sixTimes) / 6.0;
}

/// A number for a message: up to six significant digits.
std::string numberText(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", x);
  return text;
}

}  // namespace

SurfaceMesh readSurface(const std::string& path) {
  const std::string e = lowerExtension(path);
  // TetGen's loaders read a file by its name until its end: a FIFO named
  // like a surface would block them, a link to /dev/zero never end. Only a
  // regular file is handed to them (a .poly's points may be in the .node
  // file next to it).
  for (const std::string& file : {path, e == ".poly" ? path.substr(0, path.size() - 5) + ".node" : path}) {
    struct stat status {};
    if (file != path && ::stat(file.c_str(), &status) != 0) continue;  // no .node: the points are in the .poly
    try {
      const files::RegularFile regular(file);
    } catch (const files::InputFileError& error) {
      if (error.problem() != "no such file") throw TetMeshError(error.what());
    }
  }
  tetgenio io;
  std::vector<char> name(path.begin(), path.end());
  bool ok = false;
  if (e == ".off") {
    name.push_back('\0');
    ok = io.load_off(name.data());
  } else if (e == ".stl") {
    name.push_back('\0');
    ok = io.load_stl(name.data());
  } else if (e == ".ply") {
    name.push_back('\0');
    ok = io.load_ply(name.data());
  } else if (e == ".poly") {
    name.resize(name.size() - 5);  // TetGen takes the base name
    name.push_back('\0');
    ok = io.load_poly(name.data());
  } else {
    throw TetMeshError(path + ": unknown surface format (expected .off, .stl, .ply or .poly)");
  }
  if (!ok) throw TetMeshError(path + ": cannot read the surface (missing file or format error)");
  SurfaceMesh s;
  const int base = io.firstnumber;
  s.points.resize(static_cast<std::size_t>(std::max(io.numberofpoints, 0)));
  for (std::size_t v = 0; v < s.points.size(); ++v)
    s.points[v] = {io.pointlist[3 * v], io.pointlist[3 * v + 1], io.pointlist[3 * v + 2]};
  for (int f = 0; f < io.numberoffacets; ++f) {
    const tetgenio::facet& facet = io.facetlist[f];
    for (int p = 0; p < facet.numberofpolygons; ++p) {
      const tetgenio::polygon& polygon = facet.polygonlist[p];
      std::vector<VertexId> corners;
      for (int c = 0; c < polygon.numberofvertices; ++c) {
        const long long index = static_cast<long long>(polygon.vertexlist[c]) - base;
        corners.push_back(index < 0 ? kNoVertex : static_cast<VertexId>(index));
      }
      s.polygons.push_back(std::move(corners));
    }
  }
  return s;
}

void validateSurface(const SurfaceMesh& surface, const std::string& source) {
  if (surface.points.size() < 4 || surface.polygons.size() < 4)
    throw TetMeshError(source + ": not a closed surface (" + std::to_string(surface.points.size()) + " points, " +
                       std::to_string(surface.polygons.size()) + " polygons)");
  double extent = 0.0;
  for (std::size_t v = 0; v < surface.points.size(); ++v) {
    const Vec3d p = surface.points[v];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw TetMeshError(source + ": point " + std::to_string(v) + " has a non-finite coordinate");
    extent = std::max({extent, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  }
  const SurfaceMesh s = mergeIdenticalPoints(surface);
  std::map<std::pair<VertexId, VertexId>, int> edgeUses;
  for (std::size_t f = 0; f < s.polygons.size(); ++f) {
    const auto& polygon = s.polygons[f];
    const std::string name = "polygon " + std::to_string(f);
    for (VertexId v : polygon)
      if (v >= s.points.size()) throw TetMeshError(source + ": " + name + " has a corner out of range");
    std::vector<VertexId> distinct(polygon);
    std::sort(distinct.begin(), distinct.end());
    if (std::unique(distinct.begin(), distinct.end()) - distinct.begin() < 3)
      throw TetMeshError(source + ": " + name + " has fewer than three distinct corners");
    // Twice the area vector of the polygon (Newell's formula about its first corner).
    Vec3d area{0, 0, 0};
    double longest = 0.0;
    for (std::size_t c = 0; c < polygon.size(); ++c) {
      const Vec3d a = s.points[polygon[c]], b = s.points[polygon[(c + 1) % polygon.size()]];
      area = area + cross(a - s.points[polygon[0]], b - s.points[polygon[0]]);
      longest = std::max(longest, norm(b - a));
      const VertexId u = polygon[c], w = polygon[(c + 1) % polygon.size()];
      if (u != w) ++edgeUses[{std::min(u, w), std::max(u, w)}];
    }
    if (!(norm(area) > 1e-12 * longest * longest))
      throw TetMeshError(source + ": " + name + " is degenerate (zero area)");
  }
  for (const auto& [edge, uses] : edgeUses)
    if (uses < 2)
      throw TetMeshError(source + ": the surface is not closed (the edge between points " + std::to_string(edge.first) +
                         " and " + std::to_string(edge.second) + " belongs to one polygon only)");
  (void)extent;
}

tetmesh::TetMesh tetrahedralizeSurface(const SurfaceMesh& surface, const TetrahedralizeOptions& options,
                                       const std::string& source) {
  // When TetGen's quality refinement ends. TetGen 1.5's documentation of
  // -q: Shewchuk's Delaunay refinement, which it uses, is proven to end with
  // no tetrahedron's radius-edge ratio above 2.0 provided no angle or
  // dihedral angle of the input is below 60 degrees; in practice it often
  // ends for bounds down to about 1.4 or somewhat lower; and a bound too
  // small (near or below 1) may make TetGen run for ever. Measured with
  // TetGen 1.5.0 on the unit cube with a volume bound of 0.001: 1.05 ends
  // after 5,300 points, 1.02 and 1.01 were still adding points after 30 s
  // (1.0 is the case that never ended). Bounds below kMinimumQuality are
  // refused; between it and 2 termination is likely but not certain, so
  // every run is also bounded by the number of points TetGen may add
  // (-S), which turns a refinement that would not end into an error. The
  // second value -q can take, a minimum dihedral-angle bound, is never
  // passed (it stays 0, off): TetGen documents no termination guarantee
  // for it.
  if (!(options.quality >= kMinimumQuality) || !std::isfinite(options.quality))
    throw std::invalid_argument("the quality bound (radius-edge ratio) must be at least " +
                                numberText(kMinimumQuality) + " (below it TetGen's refinement need not end)");
  if (options.maxVolume && !(*options.maxVolume > 0.0 && std::isfinite(*options.maxVolume)))
    throw std::invalid_argument("the maximum volume must be positive");
  if (options.maxAddedPoints == 0 || options.maxAddedPoints > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw std::invalid_argument("the limit on added points must be between 1 and " +
                                std::to_string(std::numeric_limits<int>::max()));
  validateSurface(surface, source);
  const SurfaceMesh s = mergeIdenticalPoints(surface);
  if (options.maxVolume) {
    // The volume bound alone asks for at least volume / bound tetrahedra;
    // TetGen's quality meshes have about six per point (fewer near the
    // boundary), so eight per point underestimates the points needed.
    const double volume = enclosedVolume(s);
    const double tetrahedra = volume / *options.maxVolume;
    const double points = tetrahedra / 8.0;
    if (points > static_cast<double>(options.maxAddedPoints))
      throw TetMeshError(source + ": a volume bound of " + numberText(*options.maxVolume) + " asks for at least " +
                         numberText(tetrahedra) + " tetrahedra in the surface's volume of " + numberText(volume) +
                         ", about " + numberText(points) + " points, more than the limit of " +
                         std::to_string(options.maxAddedPoints) + " added points");
  }

  tetgenio in, out;
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(s.points.size());
  in.pointlist = new REAL[3 * s.points.size()];
  for (std::size_t v = 0; v < s.points.size(); ++v) {
    in.pointlist[3 * v] = s.points[v].x;
    in.pointlist[3 * v + 1] = s.points[v].y;
    in.pointlist[3 * v + 2] = s.points[v].z;
  }
  in.numberoffacets = static_cast<int>(s.polygons.size());
  in.facetlist = new tetgenio::facet[s.polygons.size()];
  for (std::size_t f = 0; f < s.polygons.size(); ++f) {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = static_cast<int>(s.polygons[f].size());
    facet.polygonlist[0].vertexlist = new int[s.polygons[f].size()];
    for (std::size_t c = 0; c < s.polygons[f].size(); ++c)
      facet.polygonlist[0].vertexlist[c] = static_cast<int>(s.polygons[f][c]);
  }

  // p: the input is a piecewise linear complex; q: radius-edge bound;
  // a: volume bound; S: at most this many added points; Q: quiet. TetGen
  // parses a mutable char array.
  char text[160];
  if (options.maxVolume)
    std::snprintf(text, sizeof text, "pq%.17ga%.17gS%zuQ", options.quality, *options.maxVolume,
                  options.maxAddedPoints);
  else
    std::snprintf(text, sizeof text, "pq%.17gS%zuQ", options.quality, options.maxAddedPoints);
  std::vector<char> switches(text, text + std::char_traits<char>::length(text) + 1);
  try {
    ::tetrahedralize(switches.data(), &in, &out);
  } catch (...) {
    // TetGen reports failures by throwing an int (when it survives them).
    throw TetMeshError(source + ": TetGen failed to tetrahedralize the surface (self-intersecting or degenerate?)");
  }
  if (out.numberofpoints <= 0 || out.numberoftetrahedra <= 0)
    throw TetMeshError(source + ": TetGen produced no tetrahedra");
  // At the limit TetGen stops refining and returns a mesh that does not
  // meet the bounds: not a result.
  if (static_cast<std::size_t>(out.numberofpoints) >= s.points.size() + options.maxAddedPoints)
    throw TetMeshError(source + ": the mesh needs more than the limit of " + std::to_string(options.maxAddedPoints) +
                       " added points to meet a radius-edge bound of " + numberText(options.quality) +
                       (options.maxVolume ? " and a volume bound of " + numberText(*options.maxVolume) : "") +
                       " (TetGen stopped there)");

  tetmesh::TetMesh mesh;
  mesh.firstIndex = 0;
  mesh.points.resize(static_cast<std::size_t>(out.numberofpoints));
  for (std::size_t v = 0; v < mesh.points.size(); ++v)
    mesh.points[v] = {out.pointlist[3 * v], out.pointlist[3 * v + 1], out.pointlist[3 * v + 2]};
  const int base = out.firstnumber;
  mesh.tets.resize(static_cast<std::size_t>(out.numberoftetrahedra));
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int c = 0; c < 4; ++c)
      mesh.tets[t][c] = static_cast<VertexId>(out.tetrahedronlist[t * out.numberofcorners + c] - base);
  mesh.faces.resize(static_cast<std::size_t>(std::max(out.numberoftrifaces, 0)));
  for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    for (int c = 0; c < 3; ++c) mesh.faces[f][c] = static_cast<VertexId>(out.trifacelist[3 * f + c] - base);
  if (out.trifacemarkerlist != nullptr) {
    mesh.faceMarkers.resize(mesh.faces.size());
    for (std::size_t f = 0; f < mesh.faces.size(); ++f) mesh.faceMarkers[f] = out.trifacemarkerlist[f];
  }
  tetmesh::validateTetMesh(mesh, source, source);
  return mesh;
}

SurfaceMesh boxSurface(const Vec3d& lo, const Vec3d& hi) {
  SurfaceMesh s;
  for (int i = 0; i < 8; ++i)
    s.points.push_back({(i & 1) ? hi.x : lo.x, (i & 2) ? hi.y : lo.y, (i & 4) ? hi.z : lo.z});
  s.polygons = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  return s;
}

}  // namespace stvd::tetgen
