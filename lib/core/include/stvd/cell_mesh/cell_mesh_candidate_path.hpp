// The path of an STVD candidate on a tetrahedral mesh: the straight segment
// between two vertices, walked through the tetrahedra it crosses, refused
// where it leaves the mesh and measured with the metric interpolated along
// it.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>
#include <vector>

#include "stvd/cell_mesh/cell_mesh_domain.hpp"
#include "stvd/propagation/candidate_path.hpp"
#include "stvd/propagation/propagation.hpp"

namespace stvd {

/// Where along a candidate's segment the metric is sampled
/// (docs/tet_meshes.md compares them on exact metrics).
enum class MeshSegmentSampling {
  /// One sample per tetrahedron crossed, at the midpoint of the part of the
  /// segment inside it, weighted by that part's length: the mesh's
  /// counterpart of the grids' one sample per voxel step, and
  /// CellMeshDomain's rule.
  PerTetrahedron,
  /// One sample per chain edge the segment replaces, at the midpoints of i
  /// equal pieces: as accurate, but it needs the chain to know i.
  EqualPieces,
  /// One sample at the segment's midpoint: on a curved metric it goes below
  /// the exact distance by up to 1 % at k = 8 and more for longer chains.
  Midpoint,
};

/// The rule CellMeshDomain uses (docs/tet_meshes.md: the error table).
inline constexpr MeshSegmentSampling kMeshSegmentSampling = MeshSegmentSampling::PerTetrahedron;

/// The candidate i of neighbour w is the segment from c_{i-1} to w.
///
/// accepts(): the segment is walked from w's tetrahedra towards c_{i-1}
/// (TetrahedralRegion::walk) and refused when it leaves the mesh. A
/// candidate whose chain vertices c_0 .. c_{i-1} all lie within
/// TetrahedralRegion::convexReach of v cannot leave it and is not walked:
/// in a convex mesh none is.
///
/// length() and segmentLength(): the same walk (so a pending candidate that
/// accepts() let through unwalked is still refused if it leaves the mesh),
/// sampling the norm as Sampling says; at a sample the norm is the barycentric
/// interpolation of the four corners' parameters in the tetrahedron holding
/// it (for Riemannian norms the tensors G; as on grids, a convex
/// combination of valid parameters is valid, so no sample is cheaper than
/// the cheapest corner).
///
/// A mesh without tetrahedra (CellMeshDomain::fromEdges, fromPolyhedra)
/// measures nothing (measuresPathsOn() is false) and refuses nothing.
template <class Norm, MeshSegmentSampling Sampling = kMeshSegmentSampling>
class CellMeshCandidatePath {
 public:
  using Params = typename Norm::VertexParams;
  static_assert(std::is_trivially_copyable_v<Params> && sizeof(Params) % sizeof(float) == 0,
                "mesh segments interpolate Norm::VertexParams as a plain struct of floats");

  CellMeshCandidatePath(const CellMeshDomain& domain, const MetricField<Norm>& metric)
      : points_(domain.points().data()),
        region_(domain.tetrahedra()),
        metric_(metric),
        vertexCount_(domain.vertexCount()),
        inverseStep_(1.0 / meanEdgeLength(domain)) {}

  static constexpr bool measuresPaths() { return true; }
  static bool measuresPathsOn(const CellMeshDomain& domain) { return domain.tetrahedra() != nullptr; }
  /// Only equal pieces need the chain (to know i); the other rules measure a
  /// pending candidate from its two end points (segmentLength).
  static constexpr bool usesPlacedChain() { return Sampling == MeshSegmentSampling::EqualPieces; }

  STVD_ALWAYS_INLINE void beginChain(const VertexId* chain, int count, const Vec3f* placed) {
    chain_ = chain;
    placed_ = placed;
    mayRefuse_ = false;
    if (region_ != nullptr && count > 1) {
      // reach_[j]: the farthest of c_0 .. c_j from v, squared.
      reach_[0] = 0.f;
      for (int j = 1; j < count; ++j) reach_[j] = std::max(reach_[j - 1], dot(placed[j], placed[j]));
      const float convex = region_->convexReach(chain[0]);
      convexSquared_ = convex * convex;
      mayRefuse_ = !(reach_[count - 1] < convexSquared_);
    }
  }

  bool mayRefuse() const { return mayRefuse_; }

  /// What measuring the segment from a to b costs, in the mesh's steps: its
  /// length over the mean edge length, rounded up (a walk crosses a few
  /// tetrahedra per step).
  int steps(VertexId a, VertexId b) const {
    return static_cast<int>(std::ceil(norm(points_[b] - points_[a]) * inverseStep_));
  }
  /// The default reach of an any-angle ancestor and of a source, in steps
  /// (anyAngleReach, candidate_path.hpp).
  int defaultReach() const { return anyAngleReach(vertexCount_, false); }
  int defaultSourceReach() const { return anyAngleReach(vertexCount_, true); }

  bool accepts(int i, VertexId w) {
    if (!mayRefuse_ || reach_[i - 1] < convexSquared_) return true;
    // A vertex is relaxed from several neighbours whose best candidates
    // often start at the same chain vertex: the last walks are remembered
    // (on an L-shaped prism 38 % of the walks were repeats).
    const std::uint64_t key = (std::uint64_t{w} << 32) | chain_[i - 1];
    Walked& walked = walked_[(key * 0x9e3779b97f4a7c15ull) >> (64 - kWalkedLog2)];
    if (walked.key != key) {
      walked.key = key;
      walked.inside = region_->walk(points_, w, chain_[i - 1], kMaxSteps, [](const SegmentPiece&) {});
    }
    return walked.inside;
  }

  float length(int i, VertexId w, Vec3f e) const {
    if (region_ == nullptr) return kRefusedCandidate;
    return measure(chain_[i - 1], w, e - placed_[i - 1], Sampling == MeshSegmentSampling::EqualPieces ? i : 1);
  }

  /// length() from the candidate's end points alone, for a pending candidate.
  float segmentLength(VertexId from, VertexId w) const {
    static_assert(Sampling != MeshSegmentSampling::EqualPieces, "equal pieces need the chain (usesPlacedChain)");
    return measure(from, w, toFloat(points_[w] - points_[from]), 1);
  }

  /// Asks for the start of segmentLength's walk: the tetrahedra around w and
  /// the far end's position.
  void prefetchSegment(VertexId from, VertexId w) const {
    if (region_ == nullptr) return;
    detail::prefetch(&points_[from]);
    region_->prefetchAround(w);
  }

 private:
  static constexpr int kFloats = static_cast<int>(sizeof(Params) / sizeof(float));
  // A segment of i chain edges crosses a few tetrahedra per edge (18 for
  // k = 8 on TetGen's quality meshes); a walk that needs far more than any
  // chain or the longest reach of an any-angle ancestor (64 steps) could has
  // gone astray and is refused.
  static constexpr int kMaxSteps = 32 + 8 * (kMaxMemoryDepth + 64);

  static double meanEdgeLength(const CellMeshDomain& domain) {
    double sum = 0.0;
    std::uint64_t count = 0;
    for (VertexId v = 0; v < domain.vertexCount(); ++v)
      domain.forEachNeighbor(v, [&](VertexId, Vec3f e) {
        sum += std::sqrt(static_cast<double>(dot(e, e)));
        ++count;
      });
    return count > 0 && sum > 0.0 ? sum / static_cast<double>(count) : 1.0;
  }

  // The segment from `from` to w (its vector `segment`, from `from` to w),
  // walked from w's end and measured as Sampling says; `pieces` is i for
  // EqualPieces.
  float measure(VertexId from, VertexId w, Vec3f segment, int pieces) const {
    double total = 0.0;
    bool inside;
    if constexpr (Sampling == MeshSegmentSampling::PerTetrahedron) {
      inside = region_->walk(points_, w, from, kMaxSteps, [&](const SegmentPiece& p) {
        total += (p.s1 - p.s0) * normAt(p, 0.5 * (p.s0 + p.s1), segment);
      });
    } else {
      // Samples at s = (2m + 1) / (2n), m = 0..n-1, each for 1/n of the segment.
      const int n = pieces;
      int m = 0;
      inside = region_->walk(points_, w, from, kMaxSteps, [&](const SegmentPiece& p) {
        for (double s; m < n && (s = (2.0 * m + 1.0) / (2.0 * n)) <= p.s1; ++m) total += normAt(p, s, segment);
      });
      total /= n;
    }
    return inside ? static_cast<float>(total) : kRefusedCandidate;
  }

  // The norm of `segment` at point s of the piece: the corners' parameters
  // weighted by their barycentric coordinates there (clamped to the
  // tetrahedron, within the walk's tolerance).
  STVD_ALWAYS_INLINE float normAt(const SegmentPiece& p, double s, Vec3f segment) const {
    const TetrahedralRegion::Tetrahedron& c = region_->corners(p.tetrahedron);
    float weight[4], sum = 0.f;
    for (int k = 0; k < 4; ++k) {
      weight[k] = std::max(0.f, static_cast<float>(p.start[k] + s * p.slope[k]));
      sum += weight[k];
    }
    const float normalise = 1.f / sum;
    float g[kFloats] = {};
    for (int k = 0; k < 4; ++k) {
      float corner[kFloats];
      std::memcpy(corner, &metric_[c[k]], sizeof corner);
      const float wk = weight[k] * normalise;
      for (int f = 0; f < kFloats; ++f) g[f] += wk * corner[f];
    }
    Params params;
    std::memcpy(&params, g, sizeof params);
    return Norm::length(Norm::edgeParams(params, params), segment.x, segment.y, segment.z);
  }

  // The outcome of the last walks of accepts(), by (w, c_{i-1}).
  static constexpr int kWalkedLog2 = 12;
  struct Walked {
    std::uint64_t key = ~std::uint64_t{0};
    bool inside = false;
  };

  const Vec3d* points_;
  const TetrahedralRegion* region_;
  const MetricField<Norm>& metric_;
  const VertexId* chain_ = nullptr;
  const Vec3f* placed_ = nullptr;
  bool mayRefuse_ = false;
  VertexId vertexCount_;
  double inverseStep_;
  float convexSquared_ = 0.f;
  float reach_[kMaxChainLength];
  // Only a region that is not convex has candidates to walk in accepts().
  std::vector<Walked> walked_ = std::vector<Walked>(
      region_ != nullptr && region_->nonConvexEdgeCount() + region_->nonConvexVertexCount() > 0
          ? std::size_t{1} << kWalkedLog2
          : 0);
};

}  // namespace stvd
