// The path of an STVD candidate on a surface: the straight line across the
// faces around the predecessor chain, used only when it exists on the
// surface, and measured face by face. See docs/surfaces.md.
#pragma once

#include <cstdint>
#include <vector>

#include "stvd/propagation/candidate_path.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/surface/surface_domain.hpp"

namespace stvd {

/// On a surface the candidate i of neighbour w (chain c_0 = v, c_1, ...)
/// is the straight line from w to c_{i-1} through the faces around the
/// chain vertices c_0 .. c_{i-2} it passes: each of them on one side, the
/// fan of faces between its two chain edges on that side unfolded with the
/// faces' true corner angles (no scaling to a full turn). It exists when it
/// crosses every edge of that strip of faces between its end points (a
/// line through a convex polygon sequence: the range of directions from w
/// that cross all edges passed so far, a funnel, must hold the direction to
/// c_{i-1}); the line may cross the chain between two of its vertices,
/// which changes the side. Where the funnel holds both sides of a chain
/// vertex the walk follows both (at most kMaxSides at once) and keeps the
/// shortest line that exists. So a vertex whose angles on both sides are at
/// least pi is passed by no line close to it (the funnel cannot hold a fan
/// wider than pi), and a shortcut through a saddle, where the old 1-ring
/// rescaling squeezed the angles, is refused.
///
/// length(): the length of that line, measured piece by piece in the faces
/// it crosses, each with its face's tensor (the mean of its corners'
/// tensors, SurfaceDomain::faceTensors) restricted to the face: so every
/// distance is d(c_{i-1}) plus the length of a path on the surface under
/// the face-wise metric, never shorter than the exact geodesic (for the
/// isotropic metric, the polyhedral distance). Under a constant isotropic
/// metric the line's length is its unfolded length, computed directly.
///
/// measuresWhileChecking(): one walk along the chain finds the lines of all
/// the candidates of a neighbour, and measuring them after it costs little,
/// so the propagation measures every candidate when it screens a neighbour
/// and keeps the shortest, instead of deferring the screen's favourite (on
/// surfaces the screen, the paper's rule on the rescaled unfolding, ranks
/// candidates badly where the surface is curved; docs/surfaces.md).
/// A polygon enters a fan as the triangle of its corner at the fan's
/// centre (a convex polygon holds it), so lines are refused that a
/// polygon would hold further from the chain.
///
/// A line the funnel refuses may still exist where the surface is flat:
/// it leaves the strip of faces around the chain but stays in the plane.
/// Such a line is walked instead, from w straight towards c_{i-1} across
/// whatever faces it meets (flatWalk): it exists when every face it crosses
/// lies in the plane of the first (their unit normals within
/// kFlatTolerance) and it arrives at c_{i-1}, and it is then measured face
/// by face as the funnel's lines are (through a vertex on its way into the
/// corner beyond it; along an edge with the dearer of the edge's faces). It
/// is refused when it meets a face out of that plane or the surface's
/// boundary (a hole is never crossed): on a curved surface nothing
/// changes.
class SurfaceCandidatePath {
 public:
  /// Lines are checked and measured for ChainMeasure::Segment only: the
  /// chain rules measure the chain unfolded with rescaled angles, which a
  /// real line does not repair, and stay as the paper defines them.
  SurfaceCandidatePath(const SurfaceDomain& surface, const RiemannianMetric& metric,
                       const PropagationOptions& options);

  static constexpr bool measuresPaths() { return true; }
  /// A line's length depends on the chain it was unfolded along: a pending
  /// candidate is measured through beginChain() and length().
  static constexpr bool usesPlacedChain() { return true; }

  void beginChain(const VertexId* chain, int count, const Vec3f*) {
    chain_ = chain;
    count_ = count;
    if (!checksLines_) return;
    // Where each chain vertex has its neighbours along the chain, for
    // every line walked past it.
    for (int j = 0; j + 1 < count; ++j) {
      if (j > 0) previousEntry_[j] = surface_.ringIndex(chain[j], chain[j - 1]);
      nextEntry_[j] = surface_.ringIndex(chain[j], chain[j + 1]);
    }
  }
  bool mayRefuse() const { return checksLines_; }
  bool accepts(int i, VertexId w);
  float length(int i, VertexId w, Vec3f e);
  bool measuresWhileChecking() const { return checksLines_; }
  /// Source factoring (detail::OffersSourceLines): the line from w straight
  /// to the source s where the surface is flat between them, walked and
  /// measured as a refused candidate's line is (flatWalk); the segment
  /// measure only, as for every line.
  bool offersSourceLines() const { return checksLines_; }
  float sourceLineLength(VertexId w, VertexId s) const { return flatWalk(w, s, kMaxSourceLineFaces); }

  /// Most sides followed at once; a walk that would need more keeps the
  /// first ones (refusing a line is always safe, it only costs accuracy).
  static constexpr int kMaxSides = 16;
  /// Largest difference of two faces' unit normals for a walked line to
  /// treat them as one plane (flatWalk): far below any curvature a mesh
  /// means, far above the rounding of a plane's vertices in space.
  static constexpr double kFlatTolerance = 1e-9;
  /// Most faces a walked line may cross.
  static constexpr int kMaxWalkedFaces = 256;
  /// Most faces a source's line may cross. Every vertex within reach walks
  /// one, so on a large flat mesh the cost grows with the reach cubed:
  /// measured (k = 8) on the isotropic jittered 200 x 200 plane of
  /// bench/surface_speed.cpp, seeded in a corner, 64 faces cost nothing,
  /// 128 +15 % and 256 +180 to +210 % of its 80 ms; on issue 33's planes (100 x 100,
  /// seeded in the middle) mean / largest error 64: 0.058 / 2.2 % (regular),
  /// 0.083 / 4.9 % (Delaunay); 128: 0.0004 / 0.03 %, 0.006 / 1.4 %; 256:
  /// exact up to float rounding (docs/surfaces.md).
  static constexpr int kMaxSourceLineFaces = 128;

 private:
  struct Walk;
  /// The lines from w to every chain vertex c_1 .. c_{count-1} that exist:
  /// bit i of `valid` for candidate i, its unfolded length, the sides it
  /// passes the chain vertices on (bit j: c_j counter-clockwise) and where
  /// c_{i-1} lies in the plane of the walk. One walk along the chain finds
  /// them all, and the propagation asks for the candidates of one neighbour
  /// one after the other, so the last walk is kept.
  struct Lines {
    VertexId v = kNoVertex, w = kNoVertex;
    int count = 0;
    std::uint32_t valid = 0;
    std::uint32_t walked = 0;  // bit i: candidate i's line found by flatWalk, length[i] measured
    double length[kMaxMemoryDepth + 1];
    std::uint32_t sides[kMaxMemoryDepth + 1];
    double targetX[kMaxMemoryDepth + 1], targetY[kMaxMemoryDepth + 1];
  };
  const Lines& lines(VertexId w);
  void trace(VertexId w, Lines& lines) const;
  /// The straight line from w to t across a flat part of the surface,
  /// measured face by face; kRefusedCandidate where there is none or it
  /// crosses more than maxFaces faces (see the class comment).
  float flatWalk(VertexId w, VertexId t, int maxFaces) const;
  Lines lines_;
  const SurfaceDomain& surface_;
  bool checksLines_;
  std::vector<SymTensor3> faceTensor_;
  float isotropicScale_ = 0.f;  // sqrt(s) when every tensor is s I, else 0
  const VertexId* chain_ = nullptr;
  int count_ = 0;
  std::uint32_t previousEntry_[kMaxMemoryDepth], nextEntry_[kMaxMemoryDepth];
};

}  // namespace stvd
