#include "stvd/surface/surface_domain.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "stvd/system/parallel_tasks.hpp"

namespace stvd {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Building the surface runs its per-vertex and per-face loops on two
/// threads from this many corners on (a cortex of 163,842 vertices has
/// 983,040), in blocks of kBlock vertices or faces.
constexpr std::size_t kParallelCorners = std::size_t{1} << 16;
constexpr std::size_t kBlock = 4096;

Vec3d unitOr(Vec3d v, Vec3d fallback) {
  const double n = norm(v);
  return n > 0.0 && std::isfinite(n) ? (1.0 / n) * v : fallback;
}

/// Any unit vector orthogonal to the unit vector n.
Vec3d anyOrthogonal(Vec3d n) {
  const Vec3d helper = std::abs(n.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  return unitOr(cross(n, helper), {1, 0, 0});
}

std::string edgeName(VertexId a, VertexId b) {
  return "(" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

std::uint64_t directedKey(VertexId a, VertexId b) {
  return (static_cast<std::uint64_t>(a) << 32) | b;
}

/// One face side of an undirected edge.
struct EdgeSide {
  std::uint64_t key;  // smaller vertex << 32 | larger vertex
  std::uint32_t face;
  bool forward;  // the face runs from the smaller to the larger vertex
};

/// Re-orients the faces consistently per component of faces, reversing the
/// fewest needed to agree with the lowest-numbered face of each; throws for
/// an edge of more than two faces and for a non-orientable component. Only
/// called for a mesh whose half-edges are not already paired (a manifold,
/// consistently oriented mesh has each directed edge once and its opposite
/// at most once, which the constructor checks on its corner lists).
void orientConsistently(PolygonList& faces, std::size_t n) {
  const std::size_t faceCount = faces.faceCount();
  std::vector<EdgeSide> sides;
  sides.reserve(faces.faceVertex.size());
  for (std::uint32_t f = 0; f < faceCount; ++f) {
    const std::uint32_t b = faces.faceStart[f], e = faces.faceStart[f + 1];
    for (std::uint32_t c = b; c < e; ++c) {
      const VertexId u = faces.faceVertex[c];
      const VertexId w = faces.faceVertex[c + 1 < e ? c + 1 : b];
      sides.push_back({directedKey(std::min(u, w), std::max(u, w)), f, u < w});
    }
  }
  // Sorted by edge: bucketed by the smaller vertex (linear), then each
  // vertex's few sides by the larger one.
  {
    std::vector<std::uint32_t> bucket(n + 1, 0);
    for (const EdgeSide& side : sides) ++bucket[(side.key >> 32) + 1];
    for (std::size_t v = 0; v < n; ++v) bucket[v + 1] += bucket[v];
    std::vector<EdgeSide> sorted(sides.size());
    for (const EdgeSide& side : sides) sorted[bucket[side.key >> 32]++] = side;
    // bucket[v] is now the end of v's sides, the start of v + 1's.
    std::uint32_t begin = 0;
    for (std::size_t v = 0; v < n; ++v) {
      const std::uint32_t end = bucket[v];
      const auto byKey = [](const EdgeSide& a, const EdgeSide& b) { return a.key < b.key; };
      if (end - begin > 16) {  // a vertex of many faces (a fan's centre)
        std::sort(sorted.begin() + begin, sorted.begin() + end, byKey);
      } else {
        for (std::uint32_t i = begin + 1; i < end; ++i)  // insertion sort: a handful each
          for (std::uint32_t j = i; j > begin && byKey(sorted[j], sorted[j - 1]); --j) std::swap(sorted[j], sorted[j - 1]);
      }
      begin = end;
    }
    sides.swap(sorted);
  }

  // Face adjacency across interior edges; `same` when both faces run along
  // the edge in the same direction (one of them must be flipped).
  std::vector<std::uint32_t> adjStart(faceCount + 1, 0);
  for (std::size_t i = 0; i < sides.size();) {
    std::size_t j = i;
    while (j < sides.size() && sides[j].key == sides[i].key) ++j;
    if (j - i > 2)
      throw SurfaceError("edge " + edgeName(static_cast<VertexId>(sides[i].key >> 32),
                                            static_cast<VertexId>(sides[i].key)) +
                         " is shared by " + std::to_string(j - i) +
                         " faces: the surface is not a 2-manifold");
    if (j - i == 2) {
      ++adjStart[sides[i].face + 1];
      ++adjStart[sides[i + 1].face + 1];
    }
    i = j;
  }
  for (std::size_t f = 0; f < faceCount; ++f) adjStart[f + 1] += adjStart[f];
  std::vector<std::pair<std::uint32_t, bool>> adj(adjStart.back());
  {
    std::vector<std::uint32_t> fill(adjStart.begin(), adjStart.end() - 1);
    for (std::size_t i = 0; i + 1 < sides.size(); ++i) {
      if (sides[i].key != sides[i + 1].key) continue;
      const bool same = sides[i].forward == sides[i + 1].forward;
      adj[fill[sides[i].face]++] = {sides[i + 1].face, same};
      adj[fill[sides[i + 1].face]++] = {sides[i].face, same};
      ++i;
    }
  }
  // Consistent orientation per component of faces (breadth first).
  std::vector<std::int8_t> flip(faceCount, -1);
  std::vector<std::uint32_t> queue;
  for (std::uint32_t root = 0; root < faceCount; ++root) {
    if (flip[root] >= 0) continue;
    flip[root] = 0;
    queue.assign(1, root);
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const std::uint32_t f = queue[q];
      for (std::uint32_t a = adjStart[f]; a < adjStart[f + 1]; ++a) {
        const auto [g, same] = adj[a];
        const std::int8_t want = static_cast<std::int8_t>(flip[f] ^ (same ? 1 : 0));
        if (flip[g] < 0) {
          flip[g] = want;
          queue.push_back(g);
        } else if (flip[g] != want) {
          throw SurfaceError("faces " + std::to_string(f) + " and " + std::to_string(g) +
                             " cannot be oriented consistently: the surface is not orientable");
        }
      }
    }
  }
  for (std::uint32_t f = 0; f < faceCount; ++f)
    if (flip[f] == 1)
      std::reverse(faces.faceVertex.begin() + faces.faceStart[f], faces.faceVertex.begin() + faces.faceStart[f + 1]);
}

}  // namespace

SurfaceDomain::SurfaceDomain(std::vector<Vec3d> points, const PolygonList& faces)
    : points_(std::move(points)), faces_(faces) {
  const std::size_t n = points_.size();
  const std::size_t faceCount = faces_.faceCount();
  if (faces_.faceStart.empty() || faces_.faceStart.back() != faces_.faceVertex.size())
    throw SurfaceError("inconsistent polygon list");
  if (n >= kNoVertex) throw SurfaceError("too many vertices");
  for (const Vec3d& p : points_)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw SurfaceError("vertex " + std::to_string(&p - points_.data()) +
                         " has a coordinate that is not a finite number");

  // Faces: at least 3 distinct vertices, indices in range.
  std::vector<VertexId> largeFace;
  for (std::uint32_t f = 0; f < faceCount; ++f) {
    const std::uint32_t b = faces_.faceStart[f], e = faces_.faceStart[f + 1];
    if (e - b < 3)
      throw SurfaceError("face " + std::to_string(f) + " has " + std::to_string(e - b) +
                         " vertices; a face needs at least 3");
    for (std::uint32_t c = b; c < e; ++c)
      if (faces_.faceVertex[c] >= n)
        throw SurfaceError("face " + std::to_string(f) + " refers to vertex " + std::to_string(faces_.faceVertex[c]) +
                           " but there are " + std::to_string(n) + " vertices");
    // A repeated vertex: pairwise for small faces (no allocation per face),
    // sorted for large polygons.
    bool repeated = false;
    if (e - b <= 8) {
      for (std::uint32_t c = b; c < e && !repeated; ++c)
        for (std::uint32_t d = c + 1; d < e; ++d) repeated = repeated || faces_.faceVertex[c] == faces_.faceVertex[d];
    } else {
      largeFace.assign(faces_.faceVertex.begin() + b, faces_.faceVertex.begin() + e);
      std::sort(largeFace.begin(), largeFace.end());
      repeated = std::adjacent_find(largeFace.begin(), largeFace.end()) != largeFace.end();
    }
    if (repeated) throw SurfaceError("face " + std::to_string(f) + " uses a vertex twice");
  }

  // Per vertex its corners (indices into faceVertex) in increasing order, a
  // counting sort, as slots: per slot the vertex the corner's half-edge
  // leads to and the vertex before the corner in its face; per corner its
  // slot.
  const std::size_t cornerCount = faces_.faceVertex.size();
  std::vector<std::uint32_t> cornerStart(n + 1, 0);
  for (std::uint32_t c = 0; c < cornerCount; ++c) ++cornerStart[faces_.faceVertex[c] + 1];
  for (std::size_t v = 0; v < n; ++v) cornerStart[v + 1] += cornerStart[v];
  std::vector<std::uint32_t> slotOf(cornerCount);
  std::vector<VertexId> leadsTo(cornerCount), comesFrom(cornerCount);
  const auto listCorners = [&] {
    std::vector<std::uint32_t> fill(cornerStart.begin(), cornerStart.end() - 1);
    for (std::uint32_t f = 0; f < faceCount; ++f) {
      const std::uint32_t b = faces_.faceStart[f], e = faces_.faceStart[f + 1];
      for (std::uint32_t c = b; c < e; ++c) {
        const std::uint32_t slot = fill[faces_.faceVertex[c]]++;
        slotOf[c] = slot;
        leadsTo[slot] = faces_.faceVertex[c + 1 < e ? c + 1 : b];
        comesFrom[slot] = faces_.faceVertex[c > b ? c - 1 : e - 1];
      }
    }
  };
  listCorners();
  // A vertex of many corners (a fan's centre) is searched through its
  // slots sorted by the vertex they lead to (then by number), so that it
  // costs no quadratic scan; the few slots of the others, linearly.
  constexpr std::uint32_t kLinearSearch = 32;
  std::vector<std::pair<VertexId, std::uint32_t>> byNext;
  const auto sortLargeVertices = [&] {
    byNext.clear();
    for (std::size_t v = 0; v < n; ++v) {
      const std::uint32_t b = cornerStart[v], e = cornerStart[v + 1];
      if (e - b <= kLinearSearch) continue;
      if (byNext.empty()) byNext.resize(cornerCount);
      for (std::uint32_t i = b; i < e; ++i) byNext[i] = {leadsTo[i], i};
      std::sort(byNext.begin() + b, byNext.begin() + e);
    }
  };
  // The slots of `from` whose half-edge leads to `to`: how many, and the
  // first (the lowest-numbered corner).
  const auto halfEdges = [&](VertexId from, VertexId to, std::uint32_t& first) {
    const std::uint32_t b = cornerStart[from], e = cornerStart[from + 1];
    std::uint32_t count = 0;
    if (e - b <= kLinearSearch) {
      for (std::uint32_t i = b; i < e; ++i)
        if (leadsTo[i] == to && count++ == 0) first = i;
    } else {
      const auto last = byNext.begin() + e;
      auto it = std::lower_bound(byNext.begin() + b, last, std::make_pair(to, std::uint32_t{0}));
      if (it != last && it->first == to) first = it->second;
      for (; it != last && it->first == to; ++it) ++count;
    }
    return count;
  };
  // Which half-edges (v -> w) have a twin (w -> v). Where every directed
  // edge is used once and its opposite at most once, the faces are
  // consistently oriented 2-manifold sides already; otherwise they are
  // oriented (or the mesh refused) by matching edge sides, and the lists
  // made again.
  std::vector<std::uint8_t> twinless(cornerCount, 0);  // per slot
  // The per-vertex loops below run on two threads, each on whole blocks of
  // vertices (or faces) that write only their own entries: the results are
  // the same bits for any number of threads.
  const unsigned threads = cornerCount >= kParallelCorners ? 2 : 1;
  const std::size_t vertexBlocks = (n + kBlock - 1) / kBlock, faceBlocks = (faceCount + kBlock - 1) / kBlock;
  const auto blockEnd = [](std::size_t block, std::size_t count) { return std::min(count, (block + 1) * kBlock); };
  const auto findTwins = [&] {
    std::vector<std::uint8_t> blockPaired(vertexBlocks, 1);
    forEachTaskInParallel(vertexBlocks, threads, [&](std::size_t block) {
      for (std::size_t v = block * kBlock; v < blockEnd(block, n); ++v)
        for (std::uint32_t i = cornerStart[v]; i < cornerStart[v + 1]; ++i) {
          const VertexId w = leadsTo[i];
          std::uint32_t first = 0;
          if (halfEdges(static_cast<VertexId>(v), w, first) != 1) blockPaired[block] = 0;
          const std::uint32_t opposite = halfEdges(w, static_cast<VertexId>(v), first);
          if (opposite > 1) blockPaired[block] = 0;
          twinless[i] = opposite == 0 ? 1 : 0;
        }
    });
    return std::find(blockPaired.begin(), blockPaired.end(), 0) == blockPaired.end();
  };
  sortLargeVertices();
  if (!findTwins()) {
    orientConsistently(faces_, n);
    listCorners();
    sortLargeVertices();
    findTwins();
  }

  // 1-rings, counter-clockwise. Every corner is one ring entry, and a
  // boundary fan (a vertex with a half-edge without twin) one more, so the
  // rings are laid out before they are walked; the walk around each vertex
  // (among its own slots) gives each corner its entry, and the geometry is
  // then written face by face, so that a face's points are read once. (A
  // walk from corner to corner through the whole mesh, reading points as it
  // went, waited on memory at every step: most of the time of building a
  // cortex.)
  normals_.assign(n, Vec3d{0, 0, 1});
  tangents_.assign(n, Vec3d{1, 0, 0});
  angleSum_.assign(n, 0.0);
  boundary_.assign(n, 0);
  ringStart_.assign(n + 1, 0);
  for (std::size_t v = 0; v < n; ++v) {
    bool open = false;
    for (std::uint32_t i = cornerStart[v]; i < cornerStart[v + 1] && !open; ++i) open = twinless[i] != 0;
    boundary_[v] = open ? 1 : 0;
    ringStart_[v + 1] = ringStart_[v] + (cornerStart[v + 1] - cornerStart[v]) + (open ? 1 : 0);
  }
  const std::size_t ringSize = ringStart_[n];
  ringNeighbor_.resize(ringSize);
  ringCorner_.resize(ringSize);
  ringAngle_.resize(ringSize);
  ringEdgeX_.resize(ringSize);
  ringEdgeY_.resize(ringSize);
  ringLength_.resize(ringSize);
  ringDirectionX_.resize(ringSize);
  ringDirectionY_.resize(ringSize);
  std::vector<std::uint32_t> entryOf(cornerCount);  // per slot
  // A vertex that is no single fan throws; the lowest-numbered one is
  // reported, as its block is the lowest that failed.
  forEachTaskInParallel(vertexBlocks, threads, [&](std::size_t block) {
    for (std::size_t v = block * kBlock; v < blockEnd(block, n); ++v) {
      const std::uint32_t cb = cornerStart[v], ce = cornerStart[v + 1];
      if (cb == ce) continue;  // isolated vertex: no neighbours
      // A boundary fan starts at the first corner whose outgoing edge has
      // no twin.
      std::uint32_t start = cb;
      if (boundary_[v])
        while (!twinless[start]) ++start;
      const std::uint32_t last = ringStart_[v + 1];
      std::uint32_t entry = ringStart_[v], walked = 0, slot = start;
      // From corner c the walk continues at the half-edge v -> prev(c) (the
      // twin of prev(c) -> v), v's lowest-numbered corner leading there. No
      // two corners continue at the same one (no edge has two sides running
      // one way), so the walk ends at a boundary or back at its start.
      for (;;) {
        ++walked;
        entryOf[slot] = entry;
        ringNeighbor_[entry++] = leadsTo[slot];
        const VertexId previous = comesFrom[slot];
        std::uint32_t following = 0;
        if (halfEdges(static_cast<VertexId>(v), previous, following) == 0) {
          // boundary: the fan ends with the edge to prev
          if (entry == last) break;  // (not a single fan: refused below)
          ringNeighbor_[entry] = previous;
          ringLength_[entry] = norm(points_[previous] - points_[v]);
          ringCorner_[entry] = {1.0, 0.0, 0.0, previous, kNoFace};
          ++entry;
          break;
        }
        slot = following;
        if (slot == start || entry == last) break;
      }
      if (walked != ce - cb)
        throw SurfaceError("vertex " + std::to_string(v) +
                           " is not a 2-manifold vertex: its faces do not form a single fan");
    }
  });
  // Per face its normal (Newell's method: also right for non-planar
  // polygons); per corner, at its ring entry, its angle as it is on the
  // surface (waiting in ringDirectionY_ until the rings are scaled) with
  // its cosine and sine, the face, and the length of the edge to the
  // corner's next vertex.
  faceNormals_.assign(faceCount, Vec3d{});
  forEachTaskInParallel(faceBlocks, threads, [&](std::size_t block) {
    for (std::size_t f = block * kBlock; f < blockEnd(block, faceCount); ++f) {
      const std::uint32_t b = faces_.faceStart[f], e = faces_.faceStart[f + 1];
      Vec3d s{};
      for (std::uint32_t c = b; c < e; ++c) {
        const Vec3d p = points_[faces_.faceVertex[c]], q = points_[faces_.faceVertex[c + 1 < e ? c + 1 : b]];
        s = s + Vec3d{(p.y - q.y) * (p.z + q.z), (p.z - q.z) * (p.x + q.x), (p.x - q.x) * (p.y + q.y)};
      }
      faceNormals_[f] = unitOr(s, {0, 0, 0});
      for (std::uint32_t c = b; c < e; ++c) {
        const Vec3d p = points_[faces_.faceVertex[c]];
        const VertexId w = faces_.faceVertex[c + 1 < e ? c + 1 : b], u = faces_.faceVertex[c > b ? c - 1 : e - 1];
        const Vec3d a = points_[w] - p, toU = points_[u] - p;
        const double alpha = std::atan2(norm(cross(a, toU)), dot(a, toU));
        const std::uint32_t entry = entryOf[slotOf[c]];
        ringDirectionY_[entry] = alpha;
        ringLength_[entry] = norm(a);
        ringCorner_[entry] = {std::cos(alpha), std::sin(alpha), 0.0, w, static_cast<std::uint32_t>(f)};
      }
    }
  });
  // Per vertex: the angles summed around the ring (the angle of each entry
  // before scaling waits in ringDirectionX_), the normal, the frame.
  forEachTaskInParallel(vertexBlocks, threads, [&](std::size_t block) {
    for (std::size_t v = block * kBlock; v < blockEnd(block, n); ++v) {
      const std::uint32_t first = ringStart_[v], last = ringStart_[v + 1];
      if (first == last) continue;  // isolated vertex
      const bool open = boundary_[v] != 0;
      const Vec3d p = points_[v];
      double angle = 0.0;
      Vec3d normal{};
      for (std::uint32_t i = first; i < last; ++i) {
        ringDirectionX_[i] = angle;
        const std::uint32_t face = ringCorner_[i].face;
        if (face == kNoFace) continue;  // the edge that ends a boundary fan
        const double alpha = ringDirectionY_[i];
        angle += alpha;
        normal = normal + alpha * faceNormals_[face];
      }
      angleSum_[v] = angle;
      const double scale = !open && angle > 0.0 ? 2.0 * kPi / angle : 1.0;
      for (std::uint32_t i = first; i < last; ++i) {
        ringAngle_[i] = static_cast<float>(ringDirectionX_[i] * scale);
        ringCorner_[i].length = ringLength_[i];
        ringDirectionX_[i] = std::cos(static_cast<double>(ringAngle_[i]));
        ringDirectionY_[i] = std::sin(static_cast<double>(ringAngle_[i]));
        ringEdgeX_[i] = static_cast<float>(ringLength_[i] * ringDirectionX_[i]);
        ringEdgeY_[i] = static_cast<float>(ringLength_[i] * ringDirectionY_[i]);
      }
      normals_[v] = unitOr(normal, Vec3d{0, 0, 1});
      const Vec3d d = points_[ringNeighbor_[first]] - p;
      tangents_[v] = unitOr(d - dot(d, normals_[v]) * normals_[v], anyOrthogonal(normals_[v]));
    }
  });

  // Components through edges.
  component_.assign(n, kNoVertex);
  std::vector<VertexId> stack;
  for (VertexId root = 0; root < n; ++root) {
    if (component_[root] != kNoVertex) continue;
    component_[root] = componentCount_;
    stack.assign(1, root);
    while (!stack.empty()) {
      const VertexId v = stack.back();
      stack.pop_back();
      for (std::uint32_t i = ringStart_[v]; i < ringStart_[v + 1]; ++i) {
        const VertexId w = ringNeighbor_[i];
        if (component_[w] == kNoVertex) {
          component_[w] = componentCount_;
          stack.push_back(w);
        }
      }
    }
    ++componentCount_;
  }
}

std::vector<SymTensor3> SurfaceDomain::faceTensors(const RiemannianMetric& metric) const {
  std::vector<SymTensor3> tensor(faces_.faceCount());
  for (std::size_t f = 0; f < faces_.faceCount(); ++f) {
    double sum[6] = {0, 0, 0, 0, 0, 0};
    const std::uint32_t begin = faces_.faceStart[f], end = faces_.faceStart[f + 1];
    for (std::uint32_t c = begin; c < end; ++c) {
      const SymTensor3& g = metric[faces_.faceVertex[c]];
      const float component[6] = {g.xx, g.xy, g.xz, g.yy, g.yz, g.zz};
      for (int k = 0; k < 6; ++k) sum[k] += component[k];
    }
    const double w = 1.0 / (end - begin);
    tensor[f] = SymTensor3{float(w * sum[0]), float(w * sum[1]), float(w * sum[2]),
                           float(w * sum[3]), float(w * sum[4]), float(w * sum[5])};
  }
  return tensor;
}

std::vector<float> SurfaceDomain::edgeTensors(const RiemannianMetric& metric, EdgeTensorRule rule) const {
  const std::vector<SymTensor3> face =
      rule == EdgeTensorRule::CheaperFace ? faceTensors(metric) : std::vector<SymTensor3>();
  auto unit = [](Vec3f v) {
    const float n2 = dot(v, v);
    return n2 > 0.f ? (1.f / std::sqrt(n2)) * v : Vec3f{};
  };
  std::vector<Vec3f> normal(points_.size());
  for (std::size_t v = 0; v < points_.size(); ++v) normal[v] = toFloat(normals_[v]);
  std::vector<float> tensor(3 * ringNeighbor_.size());
  for (VertexId v = 0; v < vertexCount(); ++v) {
    const std::uint32_t begin = ringStart_[v], end = ringStart_[v + 1];
    for (std::uint32_t i = begin; i < end; ++i) {
      // Single precision, as the chain rules always measured: the same
      // expression whichever way the edge is walked, so both directions get
      // the same bits.
      const VertexId w = ringNeighbor_[i];
      const Vec3f d = unit(toFloat(points_[w] - points_[v]));
      const Vec3f nE = unit(normal[v] + normal[w]);
      const Vec3f p = unit(Vec3f{nE.y * d.z - nE.z * d.y, nE.z * d.x - nE.x * d.z, nE.x * d.y - nE.y * d.x});
      SymTensor3 g = RiemannianNorm::edgeParams(metric[v], metric[w]);
      if (rule == EdgeTensorRule::CheaperFace) {
        // The faces on either side: the one after entry i and the one
        // before it (around a full ring, the last entry's; at the start of
        // a boundary fan that entry has none).
        const std::uint32_t after = ringCorner_[i].face, other = ringFaceBefore(v, i);
        const std::uint32_t first = after != kNoFace ? after : other;
        g = face[first];
        if (after != kNoFace && other != kNoFace && face[other].quadraticForm(d) < g.quadraticForm(d))
          g = face[other];
      }
      const Vec3f gd = g.apply(d);
      tensor[3 * i] = dot(d, gd);
      tensor[3 * i + 1] = dot(p, gd);
      tensor[3 * i + 2] = g.quadraticForm(p);
    }
  }
  return tensor;
}

}  // namespace stvd
