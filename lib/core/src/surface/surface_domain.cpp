#include "stvd/surface/surface_domain.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace stvd {
namespace {

constexpr double kPi = 3.14159265358979323846;

Vec3d cross(Vec3d a, Vec3d b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}

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
  std::vector<EdgeSide> sides;
  sides.reserve(faces_.faceVertex.size());
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
    for (std::uint32_t c = b; c < e; ++c) {
      const VertexId u = faces_.faceVertex[c];
      const VertexId w = faces_.faceVertex[c + 1 < e ? c + 1 : b];
      sides.push_back({directedKey(std::min(u, w), std::max(u, w)), f, u < w});
    }
  }
  // Sorted by edge: bucketed by the smaller vertex (linear), then each
  // vertex's few sides by the larger one (std::sort of all the sides was a
  // tenth of building a cortex).
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
      std::reverse(faces_.faceVertex.begin() + faces_.faceStart[f],
                   faces_.faceVertex.begin() + faces_.faceStart[f + 1]);

  // The corners of every vertex, and each half-edge's twin.
  const std::size_t cornerCount = faces_.faceVertex.size();
  std::vector<std::uint32_t> cornerFace(cornerCount);
  std::vector<std::uint32_t> cornerStart(n + 1, 0);
  auto nextOf = [&](std::uint32_t c) {
    const std::uint32_t f = cornerFace[c];
    return faces_.faceVertex[c + 1 < faces_.faceStart[f + 1] ? c + 1 : faces_.faceStart[f]];
  };
  auto prevOf = [&](std::uint32_t c) {
    const std::uint32_t f = cornerFace[c];
    return faces_.faceVertex[c > faces_.faceStart[f] ? c - 1 : faces_.faceStart[f + 1] - 1];
  };
  for (std::uint32_t f = 0; f < faceCount; ++f)
    for (std::uint32_t c = faces_.faceStart[f]; c < faces_.faceStart[f + 1]; ++c) cornerFace[c] = f;
  for (std::uint32_t c = 0; c < cornerCount; ++c) ++cornerStart[faces_.faceVertex[c] + 1];
  for (std::size_t v = 0; v < n; ++v) cornerStart[v + 1] += cornerStart[v];
  std::vector<std::uint32_t> corners(cornerCount);
  {
    std::vector<std::uint32_t> fill(cornerStart.begin(), cornerStart.end() - 1);
    for (std::uint32_t c = 0; c < cornerCount; ++c) corners[fill[faces_.faceVertex[c]]++] = c;
  }
  // The twin of each half-edge (v -> next): the corner of the half-edge
  // (next -> v), the first in corner order, or -1 on a boundary; found
  // among next's few corners. (A cortex of 163,842 vertices walked its
  // rings with a binary search over all half-edges per step: a third of
  // building the surface.)
  std::vector<std::int64_t> twin(cornerCount, -1);
  {
    // Each vertex's corners by the vertex they lead to, then by number: a
    // binary search each (a vertex of many faces costs no quadratic scan).
    std::vector<std::pair<VertexId, std::uint32_t>> byNext(cornerCount);
    for (std::size_t v = 0; v < n; ++v) {
      for (std::uint32_t i = cornerStart[v]; i < cornerStart[v + 1]; ++i) byNext[i] = {nextOf(corners[i]), corners[i]};
      std::sort(byNext.begin() + cornerStart[v], byNext.begin() + cornerStart[v + 1]);
    }
    for (std::uint32_t c = 0; c < cornerCount; ++c) {
      const VertexId v = faces_.faceVertex[c], w = nextOf(c);
      const auto first = byNext.begin() + cornerStart[w], last = byNext.begin() + cornerStart[w + 1];
      const auto it = std::lower_bound(first, last, std::make_pair(v, std::uint32_t{0}));
      if (it != last && it->first == v) twin[c] = it->second;
    }
  }
  auto previousCorner = [&](std::uint32_t c) {
    const std::uint32_t f = cornerFace[c];
    return c > faces_.faceStart[f] ? c - 1 : faces_.faceStart[f + 1] - 1;
  };
  auto cornerAngle = [&](std::uint32_t c) {
    const Vec3d p = points_[faces_.faceVertex[c]];
    const Vec3d a = points_[nextOf(c)] - p, b = points_[prevOf(c)] - p;
    return std::atan2(norm(cross(a, b)), dot(a, b));
  };

  // Face normals (Newell's method: also right for non-planar polygons).
  std::vector<Vec3d> faceNormal(faceCount);
  for (std::uint32_t f = 0; f < faceCount; ++f) {
    Vec3d s{};
    for (std::uint32_t c = faces_.faceStart[f]; c < faces_.faceStart[f + 1]; ++c) {
      const Vec3d p = points_[faces_.faceVertex[c]], q = points_[nextOf(c)];
      s = s + Vec3d{(p.y - q.y) * (p.z + q.z), (p.z - q.z) * (p.x + q.x),
                    (p.x - q.x) * (p.y + q.y)};
    }
    faceNormal[f] = unitOr(s, {0, 0, 0});
  }

  // 1-rings, counter-clockwise, with their angles.
  normals_.assign(n, Vec3d{0, 0, 1});
  tangents_.assign(n, Vec3d{1, 0, 0});
  angleSum_.assign(n, 0.0);
  boundary_.assign(n, 0);
  ringStart_.assign(n + 1, 0);
  // Every corner is one ring entry, and a boundary fan one more.
  ringNeighbor_.reserve(cornerCount + n);
  ringCorner_.reserve(cornerCount + n);
  ringAngle_.reserve(cornerCount + n);
  std::vector<std::uint8_t> visited(cornerCount, 0);
  std::vector<double> angles;
  for (VertexId v = 0; v < n; ++v) {
    ringStart_[v] = static_cast<std::uint32_t>(ringNeighbor_.size());
    const std::uint32_t cb = cornerStart[v], ce = cornerStart[v + 1];
    if (cb == ce) continue;  // isolated vertex: no neighbours
    // A boundary fan starts at the corner whose outgoing edge has no twin.
    std::uint32_t start = corners[cb];
    bool open = false;
    for (std::uint32_t i = cb; i < ce; ++i) {
      if (twin[corners[i]] < 0) {
        start = corners[i];
        open = true;
        break;
      }
    }
    angles.clear();
    double angle = 0.0;
    Vec3d normal{};
    std::uint32_t walked = 0;
    std::uint32_t c = start;
    for (;;) {
      visited[c] = 1;
      ++walked;
      ringNeighbor_.push_back(nextOf(c));
      angles.push_back(angle);
      const double alpha = cornerAngle(c);
      ringCorner_.push_back({std::cos(alpha), std::sin(alpha), 0.0, nextOf(c), cornerFace[c]});
      angle += alpha;
      normal = normal + alpha * faceNormal[cornerFace[c]];
      // The half-edge v -> prev(c): the twin of prev(c) -> v.
      const std::int64_t following = twin[previousCorner(c)];
      if (following < 0) {  // boundary: the fan ends with the edge to prev
        ringNeighbor_.push_back(prevOf(c));
        angles.push_back(angle);
        ringCorner_.push_back({1.0, 0.0, 0.0, prevOf(c), kNoFace});
        break;
      }
      c = static_cast<std::uint32_t>(following);
      if (c == start || visited[c]) break;
      if (walked > ce - cb) break;
    }
    if (walked != ce - cb)
      throw SurfaceError("vertex " + std::to_string(v) +
                         " is not a 2-manifold vertex: its faces do not form a single fan");
    angleSum_[v] = angle;
    boundary_[v] = open ? 1 : 0;
    const double scale = !open && angle > 0.0 ? 2.0 * kPi / angle : 1.0;
    for (const double a : angles) ringAngle_.push_back(static_cast<float>(a * scale));
    normals_[v] = unitOr(normal, Vec3d{0, 0, 1});
    const Vec3d d = points_[ringNeighbor_[ringStart_[v]]] - points_[v];
    tangents_[v] = unitOr(d - dot(d, normals_[v]) * normals_[v], anyOrthogonal(normals_[v]));
  }
  ringStart_[n] = static_cast<std::uint32_t>(ringNeighbor_.size());
  const std::size_t ringSize = ringNeighbor_.size();
  ringEdgeX_.resize(ringSize);
  ringEdgeY_.resize(ringSize);
  ringLength_.resize(ringSize);
  ringDirectionX_.resize(ringSize);
  ringDirectionY_.resize(ringSize);
  for (VertexId v = 0; v < n; ++v)
    for (std::uint32_t i = ringStart_[v]; i < ringStart_[v + 1]; ++i) {
      ringLength_[i] = norm(points_[ringNeighbor_[i]] - points_[v]);
      ringCorner_[i].length = ringLength_[i];
      ringDirectionX_[i] = std::cos(static_cast<double>(ringAngle_[i]));
      ringDirectionY_[i] = std::sin(static_cast<double>(ringAngle_[i]));
      ringEdgeX_[i] = static_cast<float>(ringLength_[i] * ringDirectionX_[i]);
      ringEdgeY_[i] = static_cast<float>(ringLength_[i] * ringDirectionY_[i]);
    }

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
        const std::uint32_t before = i > begin ? i - 1 : end - 1;
        const std::uint32_t after = ringCorner_[i].face, other = ringCorner_[before].face;
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
