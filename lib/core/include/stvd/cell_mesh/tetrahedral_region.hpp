// The tetrahedra of a cell mesh as a region of space: which tetrahedra meet
// at each vertex and across each face, how far each vertex lies from the
// places where the region is not convex, and the walk of a straight segment
// through it.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "stvd/detail/compiler.hpp"
#include "stvd/types.hpp"

namespace stvd {

class CellMeshDomain;

/// The part of a straight segment `from -> to` that lies in one tetrahedron,
/// as TetrahedralRegion::walk reports it. Points of the segment are
/// x(s) = x(from) + s (x(to) - x(from)), s in [0, 1]; the piece is
/// s0 <= s <= s1, and the barycentric coordinate of x(s) for corner c of the
/// tetrahedron is start[c] + s slope[c] (within the walk's tolerance of
/// [0, 1] on the piece).
struct SegmentPiece {
  std::uint32_t tetrahedron = 0;
  double s0 = 0.0, s1 = 0.0;
  double start[4] = {0.0, 0.0, 0.0, 0.0};
  double slope[4] = {0.0, 0.0, 0.0, 0.0};
};

/// What CellMeshDomain keeps of the tetrahedra it was built from, for the
/// paths of STVD candidates (cell_mesh_candidate_path.hpp): the corners of
/// every tetrahedron, its neighbour across each face, the tetrahedra around
/// each vertex, and per vertex how far a chain may reach before one of its
/// candidate segments could leave the region. 48 bytes per tetrahedron and
/// 16 per vertex (docs/tet_meshes.md).
///
/// The mesh is taken to be conforming, as TetGen's are: two tetrahedra meet
/// in a shared face, edge or vertex, or not at all. A face shared by more
/// than two tetrahedra is refused when the region is built.
class TetrahedralRegion {
 public:
  using Tetrahedron = std::array<VertexId, 4>;
  static constexpr std::uint32_t kNoTetrahedron = 0xffffffffu;

  std::size_t tetrahedronCount() const { return cells_.size(); }
  const Tetrahedron& corners(std::uint32_t t) const { return cells_[t].corner; }
  /// The tetrahedron across the face of t opposite its corner f, or
  /// kNoTetrahedron where that face lies on the region's boundary.
  std::uint32_t neighbor(std::uint32_t t, int f) const { return cells_[t].neighbor[f]; }
  /// The tetrahedra that have v as a corner.
  const std::uint32_t* tetrahedraAroundBegin(VertexId v) const { return around_.data() + firstAround_[v]; }
  const std::uint32_t* tetrahedraAroundEnd(VertexId v) const { return around_.data() + firstAround_[v + 1]; }

  /// Where the region is not convex: boundary edges whose two boundary
  /// faces meet at more than 180 degrees inside (a notch, a hole, a
  /// cavity), boundary edges with other than two boundary faces, and
  /// boundary vertices where separate parts touch.
  std::size_t nonConvexEdgeCount() const { return nonConvexEdges_; }
  std::size_t nonConvexVertexCount() const { return nonConvexVertices_; }
  /// A lower bound on the distance from x(v) to the nearest of those places
  /// (+infinity when the region is convex).
  float clearance(VertexId v) const { return clearance_[v]; }
  /// The radius about x(v) within which no candidate can leave the region:
  /// when every vertex of a predecessor chain of v lies closer than this to
  /// x(v), every straight segment from one of them to a neighbour of v lies
  /// in the region (the part of the region within that ball and joined to
  /// the chain is closed, connected and locally convex, hence convex). It is
  /// clearance(v) when v's longest edge is shorter, and 0 otherwise.
  float convexReach(VertexId v) const { return convexReach_[v]; }

  /// Walks the straight segment from vertex `from` to vertex `to` through
  /// the tetrahedra, starting from those around `from` and going from each
  /// to the ones it shares the exit face, edge or vertex with, and calls
  /// piece(const SegmentPiece&) for each part of the segment in one
  /// tetrahedron, in order along it; the pieces cover [0, 1]. Returns true
  /// when the segment lies in the region, false when it leaves it (through
  /// a boundary face, or past a boundary edge or vertex with no tetrahedron
  /// beyond), crosses a flat tetrahedron, or needs more than maxSteps
  /// tetrahedra; pieces reported before a false return are to be ignored.
  ///
  /// A point counts as inside a tetrahedron when its barycentric coordinates
  /// are at least -1e-9, so segments along boundary faces and edges and
  /// through vertices are inside; exact passes through an edge or a vertex
  /// continue in the tetrahedra around it.
  template <class Piece>
  bool walk(const Vec3d* points, VertexId from, VertexId to, int maxSteps, Piece&& piece) const;

  /// Asks for the first tetrahedron a walk from v reads (a prefetch: only
  /// the caches change).
  void prefetchAround(VertexId v) const {
    const std::uint64_t first = firstAround_[v];
    if (first != firstAround_[v + 1]) detail::prefetch(&cells_[around_[first]]);
  }

 private:
  friend class CellMeshDomain;
  /// Takes tetrahedra whose corners are valid, distinct vertex numbers of
  /// `points` (CellMeshDomain::fromTetrahedra checks them). Throws
  /// std::invalid_argument for a face shared by more than two tetrahedra.
  TetrahedralRegion(const std::vector<Vec3d>& points, std::vector<Tetrahedron> tets);
  void findNeighbors(const std::vector<Vec3d>& points);
  void measureClearance(const std::vector<Vec3d>& points);

  // How far a point may lie outside a tetrahedron, in barycentric
  // coordinates, and still count as inside it.
  static constexpr double kInside = 1e-9;
  // A face whose coordinate at the exit point is below this is one the
  // segment leaves through (two such faces: through their common edge).
  static constexpr double kOnFace = 1e-7;
  // A tetrahedron continues the segment at s when its part of the segment
  // starts no later than s + kStartSlack.
  static constexpr double kStartSlack = 1e-7;
  // A tetrahedron that takes the walk further than this along the segment
  // is taken at once; below it the one that takes it furthest is sought.
  static constexpr double kClearProgress = 1e-6;
  // Steps from tetrahedron to tetrahedron around the start vertex before
  // all of them are tried in turn.
  static constexpr int kMaxTurns = 12;

  /// Barycentric coordinates of the segment in tetrahedron t; false for a
  /// flat tetrahedron.
  bool locate(const Vec3d* points, std::uint32_t t, VertexId from, VertexId to, SegmentPiece& p) const;

  // A tetrahedron's corners and its neighbours across the faces opposite
  // them, in one record: a step of the walk reads one cache line for both.
  struct alignas(32) Cell {
    Tetrahedron corner;
    std::array<std::uint32_t, 4> neighbor;
  };
  std::vector<Cell> cells_;  // ordered by smallest corner (see the constructor)
  std::vector<std::uint64_t> firstAround_;  // CSR row starts, vertexCount + 1 entries
  std::vector<std::uint32_t> around_;
  std::vector<float> clearance_, convexReach_;
  std::size_t nonConvexEdges_ = 0, nonConvexVertices_ = 0;
};

inline bool TetrahedralRegion::locate(const Vec3d* points, std::uint32_t t, VertexId from, VertexId to,
                                      SegmentPiece& p) const {
  const Tetrahedron& c = cells_[t].corner;
  const Vec3d q0 = points[c[0]];
  const Vec3d e1 = points[c[1]] - q0, e2 = points[c[2]] - q0, e3 = points[c[3]] - q0;
  auto cross = [](Vec3d a, Vec3d b) { return Vec3d{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; };
  const Vec3d n1 = cross(e2, e3), n2 = cross(e3, e1), n3 = cross(e1, e2);
  const double det = dot(e1, n1);
  // |det| <= |e1| |e2| |e3|; far below it the tetrahedron is flat.
  if (det * det <= 1e-24 * dot(e1, e1) * dot(e2, e2) * dot(e3, e3)) return false;
  const double inverse = 1.0 / det;
  auto coordinates = [&](VertexId v, double* l) {
    for (int k = 0; k < 4; ++k)
      if (c[k] == v) {  // a corner: exactly
        l[0] = l[1] = l[2] = l[3] = 0.0;
        l[k] = 1.0;
        return;
      }
    const Vec3d r = points[v] - q0;
    l[1] = dot(r, n1) * inverse;
    l[2] = dot(r, n2) * inverse;
    l[3] = dot(r, n3) * inverse;
    l[0] = 1.0 - l[1] - l[2] - l[3];
  };
  double end[4];
  coordinates(from, p.start);
  coordinates(to, end);
  for (int k = 0; k < 4; ++k) p.slope[k] = end[k] - p.start[k];
  p.tetrahedron = t;
  return true;
}

template <class Piece>
bool TetrahedralRegion::walk(const Vec3d* points, VertexId from, VertexId to, int maxSteps, Piece&& piece) const {
  // The tetrahedra that may hold the segment just after s: those around a
  // vertex (`first`), or around an edge (`first`, `second`), or one.
  enum class Around { Vertex, Edge, Face };
  Around around = Around::Vertex;
  VertexId first = from, second = kNoVertex;
  std::uint32_t across = kNoTetrahedron, previous = kNoTetrahedron;
  double s = 0.0;
  SegmentPiece best, candidate;
  for (int step = 0; step < maxSteps; ++step) {
    double bestEnd = s;
    // Locates the segment in t; when it lies in t from s on, and further
    // than in the best so far, t becomes the best. Returns kFlat for a
    // flat tetrahedron, kClear when t takes the walk clearly on (or to
    // the end), kLocated otherwise.
    enum Rating { kFlat, kLocated, kClear };
    auto rate = [&](std::uint32_t t) {
      if (!locate(points, t, from, to, candidate)) return kFlat;
      if (t == previous) return kLocated;
      // Without branches on the signs, which are as good as random: the
      // part in t starts by `by` when no face's side is entered later
      // (slope > 0) or never (slope 0), and ends where the first side is
      // left (slope < 0).
      const double by = s + kStartSlack;
      double high = 2.0;
      bool late = false;
      for (int k = 0; k < 4; ++k) {
        const double a = candidate.start[k] + kInside, d = candidate.slope[k];
        late |= (d >= 0.0) & (a < -by * d);
        const double end = a / std::min(d, -1e-300);
        high = std::min(high, d < 0.0 ? -end : 2.0);
      }
      if (late || !(high > bestEnd)) return kLocated;
      best = candidate;
      bestEnd = high;
      return bestEnd >= 1.0 || bestEnd - s > kClearProgress ? kClear : kLocated;
    };
    // The tetrahedra around `first` (that have `with` as a corner too,
    // unless it is kNoVertex) in turn, until one takes the walk clearly on.
    auto scan = [&](VertexId with) {
      for (const std::uint32_t* t = tetrahedraAroundBegin(first); t != tetrahedraAroundEnd(first); ++t) {
        const Tetrahedron& c = cells_[*t].corner;
        if (with != kNoVertex && c[0] != with && c[1] != with && c[2] != with && c[3] != with) continue;
        if (rate(*t) == kClear) return;
      }
    };
    if (around == Around::Face) {
      // The walk goes on into one of this tetrahedron's neighbours: asking
      // for their records now overlaps that load with this step's work.
      for (const std::uint32_t n : cells_[across].neighbor)
        if (n != kNoTetrahedron) detail::prefetch(&cells_[n]);
      rate(across);
    } else if (around == Around::Edge) {
      scan(second);
    } else if (step == 0) {
      // At `from`: from one of its tetrahedra to the one whose corner there
      // holds the segment's direction, each time across the face through
      // `from` that the direction lies farthest beyond (a few steps, where
      // trying every tetrahedron around `from` took ten or more).
      std::uint32_t t = tetrahedraAroundBegin(from) != tetrahedraAroundEnd(from) ? *tetrahedraAroundBegin(from)
                                                                                 : kNoTetrahedron;
      Rating rating = kFlat;
      for (int turn = 0; turn < kMaxTurns && t != kNoTetrahedron; ++turn) {
        if ((rating = rate(t)) != kLocated) break;
        const Tetrahedron& c = cells_[t].corner;
        int beyond = -1;
        double steepest = 0.0;
        for (int k = 0; k < 4; ++k)
          if (c[k] != from && candidate.slope[k] < steepest) {
            steepest = candidate.slope[k];
            beyond = k;
          }
        if (beyond < 0) break;
        t = cells_[t].neighbor[beyond];
      }
      if (rating != kClear) scan(kNoVertex);
    } else {
      scan(kNoVertex);
    }
    if (!(bestEnd > s)) return false;  // no tetrahedron holds the segment beyond s
    best.s0 = s;
    if (bestEnd >= 1.0) {
      best.s1 = 1.0;
      piece(static_cast<const SegmentPiece&>(best));
      return true;
    }
    best.s1 = bestEnd;
    piece(static_cast<const SegmentPiece&>(best));
    // The faces the segment leaves `best` through, as bits (no branch on
    // which: it is as good as random), and the corners not opposite them.
    unsigned onFace = 0;
    for (int k = 0; k < 4; ++k)
      onFace |= static_cast<unsigned>(best.start[k] + bestEnd * best.slope[k] <= kOnFace) << k;
    const unsigned corners = ~onFace & 0xfu;
    // Per set of four bits: how many are set, the lowest and the highest.
    static constexpr signed char kCount[16] = {0, 1, 1, 2, 1, 2, 2, 3, 1, 2, 2, 3, 2, 3, 3, 4};
    static constexpr signed char kLowest[16] = {-1, 0, 1, 0, 2, 0, 1, 0, 3, 0, 1, 0, 2, 0, 1, 0};
    static constexpr signed char kHighest[16] = {-1, 0, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 3, 3, 3, 3};
    const Tetrahedron& c = cells_[best.tetrahedron].corner;
    const int count = kCount[onFace];
    if (count == 1) {
      around = Around::Face;
      across = cells_[best.tetrahedron].neighbor[kLowest[onFace]];
      if (across == kNoTetrahedron) return false;  // through a boundary face
    } else if (count == 2) {
      around = Around::Edge;  // the edge of the two corners not opposite those faces
      first = c[kLowest[corners]];
      second = c[kHighest[corners]];
    } else if (count == 3) {
      around = Around::Vertex;
      first = c[kLowest[corners]];
    } else {
      return false;
    }
    previous = best.tetrahedron;
    s = bestEnd;
  }
  return false;
}

}  // namespace stvd
