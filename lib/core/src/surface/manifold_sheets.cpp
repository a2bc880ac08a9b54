#include "stvd/surface/manifold_sheets.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <stdexcept>

#include "stvd/surface/surface_propagation.hpp"

namespace stvd {
namespace {

struct Side {
  std::uint64_t key;     // the undirected edge
  std::uint32_t corner;  // the corner the side leaves from
  std::uint32_t face;
  bool forward;  // runs from the smaller vertex to the larger
};

class UnionFind {
 public:
  explicit UnionFind(std::size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0u); }
  std::uint32_t find(std::uint32_t x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  void unite(std::uint32_t a, std::uint32_t b) {
    a = find(a);
    b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);  // the smallest corner represents its class
  }

 private:
  std::vector<std::uint32_t> parent_;
};

}  // namespace

std::vector<VertexId> ManifoldSheets::copiesOf(VertexId v) const {
  std::vector<VertexId> copies{v};
  for (std::size_t i = inputVertexCount; i < original.size(); ++i)
    if (original[i] == v) copies.push_back(static_cast<VertexId>(i));
  return copies;
}

ManifoldSheets splitIntoManifoldSheets(const std::vector<Vec3d>& points, const PolygonList& faces) {
  ManifoldSheets out;
  out.inputVertexCount = points.size();
  out.points = points;
  out.faces = faces;
  out.original.resize(points.size());
  std::iota(out.original.begin(), out.original.end(), VertexId{0});
  const std::size_t faceCount = faces.faceCount();
  const std::size_t cornerCount = faces.faceVertex.size();
  if (faces.faceStart.empty() || faces.faceStart.back() != cornerCount) return out;  // SurfaceDomain says why
  for (const VertexId v : faces.faceVertex)
    if (v >= points.size()) return out;

  std::vector<std::uint32_t> cornerFace(cornerCount);
  for (std::uint32_t f = 0; f < faceCount; ++f)
    for (std::uint32_t c = faces.faceStart[f]; c < faces.faceStart[f + 1]; ++c) cornerFace[c] = f;
  auto nextCorner = [&](std::uint32_t c) {
    const std::uint32_t f = cornerFace[c];
    return c + 1 < faces.faceStart[f + 1] ? c + 1 : faces.faceStart[f];
  };
  std::vector<Side> sides;
  sides.reserve(cornerCount);
  for (std::uint32_t c = 0; c < cornerCount; ++c) {
    const VertexId u = faces.faceVertex[c], w = faces.faceVertex[nextCorner(c)];
    if (u == w) return out;  // a degenerate face: SurfaceDomain refuses it with its message
    sides.push_back({(std::uint64_t(std::min(u, w)) << 32) | std::max(u, w), c, cornerFace[c], u < w});
  }
  std::sort(sides.begin(), sides.end(), [](const Side& a, const Side& b) {
    return a.key != b.key ? a.key < b.key : a.corner < b.corner;
  });

  // Which sides stay joined: both sides of a manifold edge; of a
  // non-manifold edge the first pair in opposite directions (else the first
  // two). A face that has two sides on one edge (it passes it twice) is
  // never joined to itself.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> joined;  // pairs of side corners
  std::vector<std::uint8_t> detached(faceCount, 0);
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j].key == sides[i].key) ++j;
    const std::size_t n = j - i;
    if (n == 2 && sides[i].face != sides[i + 1].face) {
      joined.emplace_back(sides[i].corner, sides[i + 1].corner);
    } else if (n > 2) {
      ++out.nonManifoldEdges;
      std::size_t a = i, b = i + 1;
      bool found = false;
      for (std::size_t p = i; p < j && !found; ++p)
        for (std::size_t q = p + 1; q < j && !found; ++q)
          if (sides[p].forward != sides[q].forward && sides[p].face != sides[q].face) {
            a = p;
            b = q;
            found = true;
          }
      if (sides[a].face != sides[b].face) joined.emplace_back(sides[a].corner, sides[b].corner);
      for (std::size_t p = i; p < j; ++p)
        if (p != a && p != b) detached[sides[p].face] = 1;
    }
    i = j;
  }
  out.detachedFaces = static_cast<std::size_t>(std::count(detached.begin(), detached.end(), 1));

  // Corners of one vertex that are joined around it, through the joined
  // edges at it, form one fan: one vertex of the split mesh.
  UnionFind fans(cornerCount);
  for (const auto& [c, d] : joined) {
    // Side c runs u -> w (corner c at u, the next corner at w); side d runs
    // over the same edge, from either end.
    const std::uint32_t cNext = nextCorner(c), dNext = nextCorner(d);
    const bool sameDirection = faces.faceVertex[c] == faces.faceVertex[d];
    fans.unite(c, sameDirection ? d : dNext);
    fans.unite(cNext, sameDirection ? dNext : d);
  }
  // The first class of each vertex (in corner order) keeps its number.
  std::vector<std::uint8_t> vertexTaken(points.size(), 0);
  std::vector<VertexId> classVertex(cornerCount, kNoVertex);
  std::vector<std::uint8_t> vertexSplit(points.size(), 0);
  for (std::uint32_t c = 0; c < cornerCount; ++c) {
    const std::uint32_t root = fans.find(c);
    if (classVertex[root] == kNoVertex) {
      const VertexId v = faces.faceVertex[c];
      if (!vertexTaken[v]) {
        vertexTaken[v] = 1;
        classVertex[root] = v;
      } else {
        classVertex[root] = static_cast<VertexId>(out.points.size());
        out.points.push_back(points[v]);
        out.original.push_back(v);
        vertexSplit[v] = 1;
      }
    }
    out.faces.faceVertex[c] = classVertex[root];
  }
  out.addedVertices = out.points.size() - points.size();
  out.splitVertices = static_cast<std::size_t>(std::count(vertexSplit.begin(), vertexSplit.end(), 1));
  return out;
}

SurfaceDomain surfaceOfSheets(const std::vector<Vec3d>& points, const PolygonList& faces, ManifoldSheets& sheets) {
  try {
    SurfaceDomain surface(points, faces);
    sheets = ManifoldSheets{};
    sheets.inputVertexCount = points.size();
    sheets.original.resize(points.size());
    std::iota(sheets.original.begin(), sheets.original.end(), VertexId{0});
    return surface;
  } catch (const SurfaceError&) {
    sheets = splitIntoManifoldSheets(points, faces);
    if (!sheets.changed()) throw;
  }
  return SurfaceDomain(sheets.points, sheets.faces);
}

PropagationResult propagateOverSheets(const SurfaceDomain& surface, const RiemannianMetric& metric,
                                      const ManifoldSheets& sheets, const std::vector<VertexId>& sources,
                                      const PropagationOptions& options, int* runs) {
  if (sheets.original.size() != surface.vertexCount())
    throw std::invalid_argument("propagateOverSheets: the sheets are not those of the surface");
  PropagationResult best = propagate(surface, metric, sources, options);
  int count = 1;
  if (sheets.changed()) {
    const std::size_t n = sheets.inputVertexCount;
    std::vector<double> groupBest(n);
    std::vector<std::uint8_t> isSource(surface.vertexCount(), 0);
    for (const VertexId s : sources) isSource[s] = 1;
    // Each run starts again from the seeds and from every copy at its
    // group's shortest distance so far; it ends when no group improves.
    // A group improves only by a path through another group, so the runs
    // are at most one more than the splits a shortest path passes.
    for (;;) {
      std::fill(groupBest.begin(), groupBest.end(), kUnreachable);
      for (std::size_t v = 0; v < best.distance.size(); ++v)
        groupBest[sheets.original[v]] = std::min(groupBest[sheets.original[v]], best.distance[v]);
      PropagationOptions next = options;
      std::vector<VertexId> nextSources;
      bool improves = false;
      for (std::size_t v = 0; v < best.distance.size(); ++v) {
        const double g = groupBest[sheets.original[v]];
        if (isSource[v]) {
          nextSources.push_back(static_cast<VertexId>(v));
          next.sourceDistances.push_back(0.0);
        } else if (std::isfinite(g) && (sheets.original[v] != v || g < best.distance[v])) {
          // Copies, and the input vertex itself when a copy is nearer.
          if (g < best.distance[v]) improves = true;
          nextSources.push_back(static_cast<VertexId>(v));
          next.sourceDistances.push_back(g);
        }
      }
      if (!improves) break;
      const PropagationResult again = propagate(surface, metric, nextSources, next);
      ++count;
      bool changed = false;
      for (std::size_t v = 0; v < best.distance.size(); ++v)
        if (again.distance[v] < best.distance[v]) {
          best.distance[v] = again.distance[v];
          best.predecessor[v] = again.predecessor[v];
          changed = true;
        }
      best.relaxedEdges += again.relaxedEdges;
      best.measuredCandidates += again.measuredCandidates;
      best.refusedCandidates += again.refusedCandidates;
      best.peakStateBytes = std::max(best.peakStateBytes, again.peakStateBytes);
      if (again.termination != Termination::Completed) best.termination = again.termination;
      if (!changed || count > 64) break;
    }
    // The copies of a vertex are one point: one distance.
    std::fill(groupBest.begin(), groupBest.end(), kUnreachable);
    for (std::size_t v = 0; v < best.distance.size(); ++v)
      groupBest[sheets.original[v]] = std::min(groupBest[sheets.original[v]], best.distance[v]);
    best.finalizedVertices = 0;
    for (std::size_t v = 0; v < best.distance.size(); ++v) {
      best.distance[v] = groupBest[sheets.original[v]];
      best.finalizedVertices += std::isfinite(best.distance[v]) ? 1 : 0;
    }
  }
  if (runs) *runs = count;
  return best;
}

}  // namespace stvd
