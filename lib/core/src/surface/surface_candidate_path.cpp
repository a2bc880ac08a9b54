// The straight lines of STVD candidates across a surface's faces: the walk
// along the predecessor chain that decides whether a line exists (a funnel
// of directions from w through the unfolded fans of the chain vertices,
// with the faces' true angles), and its length face by face.
#include "stvd/surface/surface_candidate_path.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace stvd {
namespace {

/// A point or direction of the plane the chain's faces are unfolded into.
struct Point {
  double x, y;
};
Point operator+(Point a, Point b) { return {a.x + b.x, a.y + b.y}; }
Point operator-(Point a, Point b) { return {a.x - b.x, a.y - b.y}; }
Point operator-(Point a) { return {-a.x, -a.y}; }
Point operator*(double s, Point a) { return {s * a.x, s * a.y}; }
double cross(Point a, Point b) { return a.x * b.y - a.y * b.x; }
double magnitude(Point a) { return std::sqrt(a.x * a.x + a.y * a.y); }
/// a turned counter-clockwise by the angle whose cosine and sine are c, s.
Point turn(Point a, double c, double s) { return {a.x * c - a.y * s, a.x * s + a.y * c}; }

/// sqrt(v^T g v) in double: the length of v in a face with tensor g.
double faceLength(const SymTensor3& g, const Vec3d& v) {
  return std::sqrt(std::max(0.0, double(g.xx) * v.x * v.x + double(g.yy) * v.y * v.y + double(g.zz) * v.z * v.z +
                                     2.0 * double(g.xy) * v.x * v.y + 2.0 * double(g.xz) * v.x * v.z +
                                     2.0 * double(g.yz) * v.y * v.z));
}

/// Relative slack of the orientation tests, so that a line through a vertex
/// (a straight chain on a flat mesh) is not refused by rounding. A line
/// accepted within it passes at most 1e-9 of its length on the wrong side
/// of a vertex, where a real path through the vertex is longer by a
/// relative 1e-18.
constexpr double kSlack = 1e-9;

/// Whether b lies counter-clockwise of a, by at most pi (within kSlack).
bool counterClockwise(Point a, Point b) {
  const double c = cross(a, b);
  return c >= 0.0 || c * c <= kSlack * kSlack * ((a.x * a.x + a.y * a.y) * (b.x * b.x + b.y * b.y));
}

/// The directions from w of the lines that cross every edge passed so far:
/// counter-clockwise from `right` to `left`, an arc narrower than pi (it
/// starts as the corner at w of the first face). Vectors are relative to w.
struct Funnel {
  bool set = false;
  Point right{}, left{};

  /// Narrows the funnel to the lines that pass with a on their left and b
  /// on their right: those that cross the edge from a to b coming from the
  /// face they are in. False when no line is left. Each condition is a half
  /// turn of directions; its intersection with the arc is an arc again.
  bool pass(Point a, Point b) {
    if (!set) {
      if (!(cross(b, a) > 0.0)) return false;  // w on the edge's line
      right = b;
      left = a;
      set = true;
      return true;
    }
    return keepLeft(a) && keepRight(b);
  }

  /// Narrows the funnel to the lines that pass with a on their left.
  bool keepLeft(Point a) {
    if (!set) return true;
    const bool leftHolds = counterClockwise(left, a), rightHolds = counterClockwise(right, a);
    if (!leftHolds && !rightHolds) return false;
    if (!leftHolds) left = a;
    else if (!rightHolds) right = -a;
    return counterClockwise(right, left);
  }

  /// Narrows the funnel to the lines that pass with b on their right.
  bool keepRight(Point b) {
    if (!set) return true;
    const bool leftHolds = counterClockwise(b, left), rightHolds = counterClockwise(b, right);
    if (!leftHolds && !rightHolds) return false;
    if (!rightHolds) right = b;
    else if (!leftHolds) left = -b;
    return counterClockwise(right, left);
  }

  bool holds(Point t) const { return !set || (counterClockwise(right, t) && counterClockwise(t, left)); }

  /// Whether only the lines through one point are left (within kSlack):
  /// a line through a vertex, as along a straight chain on a flat mesh.
  bool degenerate() const {
    if (!set) return false;
    const double c = cross(right, left);
    return c * c <= kSlack * kSlack * ((right.x * right.x + right.y * right.y) * (left.x * left.x + left.y * left.y));
  }
};

}  // namespace

/// One chain vertex at a time: the fans of the chain vertices on the side
/// each is passed, unfolded with true angles into a plane where c_0 = v is
/// at the origin and w on the positive x axis.
struct SurfaceCandidatePath::Walk {
  const SurfaceDomain& surface;

  /// Where a line is at chain vertex c: c's position, the unit direction
  /// back to the previous vertex (w for c_0), the side it passes c on
  /// (counter-clockwise from the previous vertex in c's ring: the right of
  /// the chain walked from w), and the funnel.
  struct Side {
    Point at, back;
    bool counterClockwise;
    std::uint32_t sides;  // bit j: c_j passed counter-clockwise
    Funnel funnel;
  };

  /// Sweeps the fan of c from its ring entry of the previous chain vertex
  /// to that of the next one on the side's side, calling spoke(n, position, entry) for each edge
  /// strictly between (false from it ends the sweep) and face(f, n1, p1,
  /// n2, p2) for each face swept, between its edges to n1 and n2 at
  /// positions p1, p2. Leaves the position of `next` and the unit direction
  /// from it back to c. False when the side crosses a boundary or a spoke
  /// refused.
  template <class Spoke, class Face>
  bool sweep(VertexId c, std::uint32_t previousEntry, std::uint32_t nextEntry, bool ccw, Point at, Point back,
             Spoke&& spoke, Face&& face, Point& nextAt, Point& nextBack) const {
    const std::uint32_t begin = surface.ringBegin(c), end = surface.ringEnd(c);
    const std::uint32_t m = end - begin;
    const bool boundary = surface.isBoundary(c);
    std::uint32_t r = previousEntry - begin;
    const std::uint32_t q = nextEntry - begin;
    Point direction = back;
    const SurfaceDomain::RingCorner* ring = &surface.ringCorner(begin);
    VertexId from = ring[r].neighbor;
    Point fromAt = at + ring[r].length * direction;
    for (std::uint32_t steps = 0; steps < m; ++steps) {
      std::uint32_t faceEntry;
      if (ccw) {
        if (boundary && r == m - 1) return false;  // the fan ends at the boundary
        faceEntry = r;
        direction = turn(direction, ring[r].cos, ring[r].sin);
        r = r + 1 == m ? 0 : r + 1;
      } else {
        if (boundary && r == 0) return false;
        r = r == 0 ? m - 1 : r - 1;
        faceEntry = r;
        direction = turn(direction, ring[r].cos, -ring[r].sin);
      }
      const VertexId n = ring[r].neighbor;
      const Point nAt = at + ring[r].length * direction;
      face(ring[faceEntry].face, from, fromAt, n, nAt);
      if (r == q) {
        nextAt = nAt;
        nextBack = -direction;
        return true;
      }
      if (!spoke(n, nAt, begin + r)) return false;
      from = n;
      fromAt = nAt;
    }
    return false;
  }
};

SurfaceCandidatePath::SurfaceCandidatePath(const SurfaceDomain& surface, const RiemannianMetric& metric,
                                           const PropagationOptions& options)
    : surface_(surface), checksLines_(options.chainMeasure == ChainMeasure::Segment) {
  if (!checksLines_ || options.method == Method::Dijkstra) return;
  faceTensor_ = surface.faceTensors(metric);
  // A constant isotropic metric measures every line by its unfolded length.
  bool isotropic = metric.size() > 0;
  const SymTensor3 g0 = metric.size() > 0 ? metric[0] : SymTensor3{};
  for (std::size_t v = 0; v < metric.size() && isotropic; ++v) {
    const SymTensor3& g = metric[v];
    isotropic = g.xx == g0.xx && g.yy == g0.xx && g.zz == g0.xx && g.xy == 0.f && g.xz == 0.f && g.yz == 0.f;
  }
  if (isotropic && g0.xx > 0.f) isotropicScale_ = std::sqrt(g0.xx);
}

const SurfaceCandidatePath::Lines& SurfaceCandidatePath::lines(VertexId w) {
  Lines& l = lines_;
  // The chain of v never changes once v is final: the same v, w and at
  // least as many chain vertices give the same lines.
  if (l.v == chain_[0] && l.w == w && l.count >= count_) return l;
  l.v = chain_[0];
  l.w = w;
  l.count = count_;
  l.valid = 0;
  l.walked = 0;
  trace(w, l);
  // Where the funnel refused a line, the surface may still be flat along it.
  for (int i = 2; i <= count_; ++i) {
    if ((l.valid >> i) & 1u) continue;
    const float walked = flatWalk(w, chain_[i - 1], kMaxWalkedFaces);
    if (walked == kRefusedCandidate) continue;
    l.valid |= 1u << i;
    l.walked |= 1u << i;
    l.length[i] = walked;
  }
  return l;
}

float SurfaceCandidatePath::flatWalk(VertexId w, VertexId t, int maxFaces) const {
  const std::vector<Vec3d>& x = surface_.points();
  const PolygonList& faces = surface_.faces();
  const Vec3d origin = x[w];
  const Vec3d toTarget = x[t] - origin;
  const double length = norm(toTarget);
  if (!(length > 0.0)) return kRefusedCandidate;
  // The line is the X axis of a frame in the plane: e1 towards t,
  // e2 = n x e1 with n the plane's normal, taken from the first face the
  // line enters. Y within `onLine` of 0 counts as on the line.
  const Vec3d e1 = (1.0 / length) * toTarget;
  const double onLine = 1e-9 * length;
  Vec3d normal{}, e2{};
  bool planeSet = false;
  auto inPlane = [&](std::uint32_t face) {
    if (face == SurfaceDomain::kNoFace) return false;
    const Vec3d& n = surface_.faceNormal(face);
    if (!planeSet) {
      if (!(std::abs(dot(n, e1)) <= kFlatTolerance)) return false;  // the line leaves this face's plane
      normal = n;
      e2 = cross(n, e1);
      planeSet = true;
      return true;
    }
    return norm(n - normal) <= kFlatTolerance;
  };
  auto factor = [&](std::uint32_t face) { return faceLength(faceTensor_[face], e1); };
  // An edge on the line lies in the closure of both its faces: measured
  // with the dearer (the edge to ring entry `entry` of `centre`).
  auto edgeFactor = [&](VertexId centre, std::uint32_t entry) {
    const std::uint32_t after = surface_.ringFace(entry), before = surface_.ringFaceBefore(centre, entry);
    return std::max(after == SurfaceDomain::kNoFace ? 0.0 : factor(after),
                    before == SurfaceDomain::kNoFace ? 0.0 : factor(before));
  };
  auto X = [&](VertexId v) { return dot(x[v] - origin, e1); };
  auto Y = [&](VertexId v) { return dot(x[v] - origin, e2); };

  // The walk alternates between vertices on the line (w, vertices it passes
  // through, t) and the faces it crosses between them.
  VertexId vertex = w;
  std::uint32_t f = SurfaceDomain::kNoFace;
  double at = 0.0, total = 0.0;  // where the line is, and its length up to there
  for (int steps = 0; steps < maxFaces; ++steps) {
    if (vertex != kNoVertex) {
      if (vertex == t) return static_cast<float>(total);
      // Leave the vertex into the corner that holds the direction strictly,
      // or along an edge that lies on the line.
      const std::uint32_t begin = surface_.ringBegin(vertex), end = surface_.ringEnd(vertex);
      VertexId along = kNoVertex;
      double alongFactor = 0.0;
      f = SurfaceDomain::kNoFace;
      for (std::uint32_t r = begin; r < end && f == SurfaceDomain::kNoFace && along == kNoVertex; ++r) {
        const std::uint32_t face = surface_.ringFace(r);
        if (!inPlane(face)) continue;
        const std::uint32_t next = r + 1 == end ? begin : r + 1;
        const VertexId a = surface_.ringNeighbor(r), b = surface_.ringNeighbor(next);
        const double ya = Y(a), yb = Y(b);
        if (std::abs(ya) <= onLine && X(a) > at + onLine) {
          along = a;
          alongFactor = edgeFactor(vertex, r);
        } else if (std::abs(yb) <= onLine && X(b) > at + onLine) {
          along = b;
          alongFactor = edgeFactor(vertex, next);
        } else if (ya < -onLine && yb > onLine) {
          f = face;
        }
      }
      if (along != kNoVertex) {
        const double xa = X(along);
        total += (xa - at) * alongFactor;
        at = xa;
        vertex = along;
        continue;
      }
      if (f == SurfaceDomain::kNoFace) return kRefusedCandidate;
      vertex = kNoVertex;
    }
    // In face f since `at`: it reaches a vertex on the line, or leaves
    // through the edge it crosses farthest.
    if (!inPlane(f)) return kRefusedCandidate;
    const VertexId* corner = &faces.faceVertex[faces.faceStart[f]];
    const std::uint32_t m = faces.faceStart[f + 1] - faces.faceStart[f];
    double reach = kUnreachable;
    for (std::uint32_t j = 0; j < m; ++j) {
      const double xj = X(corner[j]);
      if (std::abs(Y(corner[j])) <= onLine && xj > at + onLine && xj < reach) {
        reach = xj;
        vertex = corner[j];
      }
    }
    if (vertex != kNoVertex) {
      total += (reach - at) * factor(f);
      at = reach;
      continue;
    }
    double exit = at;
    VertexId p = kNoVertex, q = kNoVertex;
    for (std::uint32_t j = 0; j < m; ++j) {
      const VertexId a = corner[j], b = corner[j + 1 == m ? 0 : j + 1];
      const double ya = Y(a), yb = Y(b);
      if (!((ya < -onLine && yb > onLine) || (ya > onLine && yb < -onLine))) continue;
      const double xa = X(a), xb = X(b);
      const double crossing = xa + (xb - xa) * ya / (ya - yb);
      if (crossing > exit) {
        exit = crossing;
        p = a;
        q = b;
      }
    }
    if (p == kNoVertex || !(exit > at + onLine) || !(exit < length)) return kRefusedCandidate;
    total += (exit - at) * factor(f);
    at = exit;
    // The face on the other side of the edge p q, none at the boundary.
    const std::uint32_t e = surface_.ringIndex(p, q);
    const std::uint32_t after = surface_.ringFace(e);
    f = after == f ? surface_.ringFaceBefore(p, e) : after;
    if (f == SurfaceDomain::kNoFace) return kRefusedCandidate;
  }
  return kRefusedCandidate;
}

bool SurfaceCandidatePath::accepts(int i, VertexId w) {
  return ((lines(w).valid >> i) & 1u) != 0;
}

void SurfaceCandidatePath::trace(VertexId w, Lines& lines) const {
  using Side = Walk::Side;
  const Walk walk{surface_};
  const VertexId* c = chain_;
  const std::uint32_t wEntry = surface_.ringIndex(c[0], w);
  const Point wAt{surface_.ringLength(wEntry), 0.0};
  auto noFace = [](std::uint32_t, VertexId, Point, VertexId, Point) {};

  // Every side the lines from w may pass the chain vertices on, one chain
  // vertex at a time; after the fan of c_j, the lines that end at c_{j+1}.
  Side sides[2][kMaxSides];
  int count = 2;
  sides[0][0] = Side{{0, 0}, {1, 0}, true, 1u, {}};
  sides[0][1] = Side{{0, 0}, {1, 0}, false, 0u, {}};
  int current = 0;
  for (int j = 0; j + 1 < count_ && count > 0; ++j) {
    const std::uint32_t previous = j == 0 ? wEntry : previousEntry_[j], next = nextEntry_[j];
    const int i = j + 2;  // the candidate that ends at c_{j+1}
    Side* out = sides[1 - current];
    int outCount = 0;
    double best = kUnreachable;
    for (int s = 0; s < count; ++s) {
      Side& side = sides[current][s];
      const bool ccw = side.counterClockwise;
      auto spoke = [&](VertexId n, Point nAt, std::uint32_t) {
        if (n == w) return false;  // the line would have to pass through its own start
        return ccw ? side.funnel.pass(side.at - wAt, nAt - wAt) : side.funnel.pass(nAt - wAt, side.at - wAt);
      };
      Point nextAt{}, nextBack{};
      if (!walk.sweep(c[j], previous, next, ccw, side.at, side.back, spoke, noFace, nextAt, nextBack)) continue;
      const Point toNext = nextAt - wAt;
      if (side.funnel.holds(toNext)) {
        const double l = magnitude(toNext);
        if (l < best) {
          best = l;
          lines.valid |= 1u << i;
          lines.length[i] = l;
          lines.sides[i] = side.sides;
          lines.targetX[i] = nextAt.x;
          lines.targetY[i] = nextAt.y;
        }
      }
      if (j + 2 >= count_) continue;
      // Pass c_{j+1} on the same side (it must then lie on the chain's side
      // of the line), or cross the chain edge c_j c_{j+1} to its other side.
      const Point at = side.at;
      side.at = nextAt;
      side.back = nextBack;
      // A line through c_{j+1} itself (a funnel narrowed to it) is followed
      // on the same side only: on either side it is the same line.
      Side change = side;
      change.counterClockwise = !ccw;
      change.sides |= (ccw ? 0u : 1u) << (j + 1);
      const bool crosses =
          ccw ? change.funnel.pass(at - wAt, toNext) : change.funnel.pass(toNext, at - wAt);
      const bool stays = ccw ? side.funnel.keepLeft(toNext) : side.funnel.keepRight(toNext);
      if (stays && outCount < kMaxSides) {
        side.sides |= (ccw ? 1u : 0u) << (j + 1);
        out[outCount++] = side;
      }
      if (crosses && !(stays && change.funnel.degenerate()) && outCount < kMaxSides) out[outCount++] = change;
    }
    current = 1 - current;
    count = outCount;
  }
}

float SurfaceCandidatePath::length(int i, VertexId w, Vec3f) {
  const Lines& l = lines(w);
  if (!((l.valid >> i) & 1u)) return kRefusedCandidate;
  if ((l.walked >> i) & 1u) return static_cast<float>(l.length[i]);  // measured as it was walked
  if (isotropicScale_ > 0.f) return static_cast<float>(isotropicScale_ * l.length[i]);
  const Walk walk{surface_};
  const VertexId* c = chain_;
  const Point wAt{surface_.ringLength(surface_.ringIndex(c[0], w)), 0.0};
  const Point target{l.targetX[i], l.targetY[i]};
  const std::uint32_t bestSides = l.sides[i];

  // Phase 2: the line w -> target measured in each face it crosses, with
  // the face's tensor: the piece between two edge crossings lies in one
  // face, where the unfolding is an isometry onto the face's plane.
  const Point d = target - wAt;
  const std::vector<Vec3d>& x = surface_.points();
  double total = 0.0, t = 0.0;
  double faceFactor = 0.0;  // length of d in the face the line is in
  bool inFace = false, degenerate = false;
  auto enter = [&](std::uint32_t f, VertexId centre, Point centreAt, VertexId n1, Point p1, VertexId n2, Point p2) {
    const Point e1 = p1 - centreAt, e2 = p2 - centreAt;
    const double det = cross(e1, e2);
    if (!(std::abs(det) > 0.0)) {  // a face without area: no line is measured through it
      degenerate = true;
      return;
    }
    const double a = cross(d, e2) / det, b = cross(e1, d) / det;
    const Vec3d v = a * (x[n1] - x[centre]) + b * (x[n2] - x[centre]);
    faceFactor = faceLength(faceTensor_[f], v);
    inFace = true;
  };
  const double dd = d.x * d.x + d.y * d.y;
  auto crossEdge = [&](Point a, Point b) {
    // The parameter u of w + u d where the line meets the edge a b: from
    // the signed distances of a and b to the line, so that a line through
    // an end point (along a straight chain on a flat mesh, or through a
    // vertex beside it) meets it there, and a line along the edge where it
    // starts; the pieces on either side are then measured in their faces.
    const double sa = cross(d, a - wAt), sb = cross(d, b - wAt);
    double u;
    if (sa != sb) {
      const double lambda = std::min(1.0, std::max(0.0, sa / (sa - sb)));
      const Point p = a + lambda * (b - a);
      u = ((p.x - wAt.x) * d.x + (p.y - wAt.y) * d.y) / dd;
    } else {
      u = std::min((a.x - wAt.x) * d.x + (a.y - wAt.y) * d.y, (b.x - wAt.x) * d.x + (b.y - wAt.y) * d.y) / dd;
    }
    const double clamped = std::min(1.0, std::max(t, u));
    total += (clamped - t) * faceFactor;
    t = clamped;
  };
  Point at{0, 0}, back{1, 0};
  bool previousCcw = true;
  const std::uint32_t wEntry = surface_.ringIndex(c[0], w);
  for (int j = 0; j + 1 < i; ++j) {
    const std::uint32_t previous = j == 0 ? wEntry : previousEntry_[j], next = nextEntry_[j];
    const bool ccw = ((bestSides >> j) & 1u) != 0;
    if (j > 0 && ccw != previousCcw) {  // crossing the chain edge c_{j-1} c_j
      const Point before = at + surface_.ringLength(previous) * back;
      if (previousCcw)
        crossEdge(before, at);
      else
        crossEdge(at, before);
      inFace = false;
    }
    // The first face of this fan is the face the line is in, unless the
    // line has just crossed the chain.
    bool first = true;
    auto face = [&](std::uint32_t f, VertexId n1, Point p1, VertexId n2, Point p2) {
      if (!(first && inFace)) enter(f, c[j], at, n1, p1, n2, p2);
      first = false;
    };
    auto spoke = [&](VertexId, Point nAt, std::uint32_t) {
      if (ccw)
        crossEdge(at, nAt);
      else
        crossEdge(nAt, at);
      return true;
    };
    Point nextAt{}, nextBack{};
    walk.sweep(c[j], previous, next, ccw, at, back, spoke, face, nextAt, nextBack);
    at = nextAt;
    back = nextBack;
    previousCcw = ccw;
  }
  total += (1.0 - t) * faceFactor;
  return degenerate ? kRefusedCandidate : static_cast<float>(total);
}

}  // namespace stvd
