// The implicit voxel grid: vertices are voxel centres, edges come from a
// stencil of index offsets. Nothing is stored per edge.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "stvd/types.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"
#include "stvd/voxel_grid/stencil.hpp"

namespace stvd {

namespace detail {
/// Division of 32-bit unsigned integers by a fixed divisor through one
/// 64x64->128 multiplication (Lemire, Kaser, Kurz 2019, "Faster remainder by
/// direct computation"). The grid needs i, j, k of many vertices per popped
/// vertex; a hardware division costs several times more.
class FixedDivisor {
 public:
  FixedDivisor() = default;
  explicit FixedDivisor(std::uint32_t d)
      : divisor_(d), magic_(d > 1 ? ~std::uint64_t{0} / d + 1 : 0) {}
  std::uint32_t divide(std::uint32_t n) const {
    if (divisor_ == 1) return n;
    return static_cast<std::uint32_t>((static_cast<unsigned __int128>(magic_) * n) >> 64);
  }
  std::uint32_t divisor() const { return divisor_; }

 private:
  std::uint32_t divisor_ = 1;
  std::uint64_t magic_ = 0;
};
}  // namespace detail

/// Integer index of a voxel.
struct VoxelIndex {
  std::int32_t i = 0, j = 0, k = 0;
};

/// Which voxels of a masked grid touch: whether two domain voxels that meet
/// only along an edge or at a corner of their cubes, with the voxels around
/// that contact outside the domain, are joined.
///
/// The domain of a masked grid is a region of space, not only a set of
/// voxels: the union of the closed cells (segments, squares and cubes
/// between neighbouring voxel centres) whose corners all lie in the domain.
/// A path may only run inside it, and every edge, stencil step and STVD
/// candidate is used only when its straight segment does (see
/// VoxelGridDomain::segmentInDomain). With `Faces` that region is all there
/// is: a diagonal line of excluded voxels is a wall, and no path passes
/// through a gap of zero width. `Edges` also joins two domain voxels that
/// are diagonal neighbours in a square of voxels whose other two are
/// outside (the 18-neighbourhood's contacts), by the straight step between
/// their centres; `Corners` also joins diagonal neighbours across a cube
/// (the 26-neighbourhood's contacts).
enum class VoxelConnectivity {
  Faces = 6,     ///< only through cells whose corners are all in the domain (default)
  Edges = 18,    ///< and across edge contacts
  Corners = 26,  ///< and across edge and corner contacts
};

/// A voxel grid seen as a graph: one vertex per voxel (linear index
/// i + nx*(j + ny*k)), one edge per stencil offset that stays inside the
/// image and the mask. Edge vectors are the physical displacements of the
/// offsets (spacing and direction cosines applied), computed once per
/// stencil offset.
class VoxelGridDomain {
 public:
  /// `mask`, when not empty, holds one byte per voxel in linear order;
  /// voxels with a zero byte are outside the domain, and `connectivity`
  /// says which contacts between domain voxels paths may pass through (see
  /// VoxelConnectivity). Throws std::invalid_argument for an invalid
  /// geometry or a mask of the wrong size.
  VoxelGridDomain(const GridGeometry& geometry, Stencil stencil,
                  std::vector<std::uint8_t> mask = {},
                  VoxelConnectivity connectivity = VoxelConnectivity::Faces);

  const GridGeometry& geometry() const { return geometry_; }
  const Stencil& stencil() const { return stencil_; }
  bool hasMask() const { return !mask_.empty(); }
  const std::vector<std::uint8_t>& mask() const { return mask_; }
  VoxelConnectivity connectivity() const { return connectivity_; }

  VertexId vertexCount() const { return vertexCount_; }
  /// Number of vertices inside the domain (all voxels, or the mask's ones).
  VertexId domainVertexCount() const { return domainVertexCount_; }
  bool contains(VertexId v) const { return v < vertexCount_ && (mask_.empty() || mask_[v] != 0); }

  /// The vertex of voxel (i, j, k). Throws std::out_of_range naming the
  /// index and the image size when (i, j, k) lies outside the image: the
  /// linear index of (nx, 0, 0) is that of (0, 1, 0), so an unchecked index
  /// past an edge would silently be another voxel.
  VertexId vertexAt(int i, int j, int k) const {
    if (!isInsideImage(i, j, k)) throwIndexOutsideImage(i, j, k);
    return vertexAtUnchecked(i, j, k);
  }
  /// vertexAt without the check, for loops that stay inside the image by
  /// construction. An index outside the image gives another voxel's vertex
  /// or one past the end.
  VertexId vertexAtUnchecked(int i, int j, int k) const {
    return static_cast<VertexId>(i) + nx_ * (static_cast<VertexId>(j) + ny_ * static_cast<VertexId>(k));
  }
  bool isInsideImage(int i, int j, int k) const {
    return i >= 0 && j >= 0 && k >= 0 && static_cast<VertexId>(i) < nx_ &&
           static_cast<VertexId>(j) < ny_ && static_cast<VertexId>(k) < nz_;
  }
  VoxelIndex indexOf(VertexId v) const {
    const std::uint32_t slice = sliceDivisor_.divide(v);
    const std::uint32_t inSlice = v - slice * nxy_;
    const std::uint32_t row = rowDivisor_.divide(inSlice);
    return {static_cast<std::int32_t>(inSlice - row * nx_), static_cast<std::int32_t>(row),
            static_cast<std::int32_t>(slice)};
  }
  /// Physical point of a voxel centre (millimetres).
  Vec3d physicalPoint(VertexId v) const {
    const VoxelIndex c = indexOf(v);
    return geometry_.indexToPhysicalPoint(c.i, c.j, c.k);
  }
  /// x(to) - x(from) in physical space, from the index difference (exact
  /// integer difference first, so large coordinates cost no precision).
  Vec3f displacement(VertexId from, VertexId to) const {
    const VoxelIndex a = indexOf(from), b = indexOf(to);
    return toFloat(geometry_.indexToPhysicalOffset(b.i - a.i, b.j - a.j, b.k - a.k));
  }

  /// x(chain[c]) - x(chain[0]) for c < count: displacement() for a whole
  /// predecessor chain, with the first voxel's index found once and single
  /// precision products of the (small) index differences.
  void placeChain(const VertexId* chain, int count, Vec3f* p) const {
    const VoxelIndex o = indexOf(chain[0]);
    p[0] = Vec3f{};
    for (int c = 1; c < count; ++c) {
      const VoxelIndex q = indexOf(chain[c]);
      p[c] = indexOffsetVector(q.i - o.i, q.j - o.j, q.k - o.k);
    }
  }
  /// The physical vector of a (small) index offset, in single precision.
  Vec3f indexOffsetVector(int di, int dj, int dk) const {
    const float a = static_cast<float>(di), b = static_cast<float>(dj), c = static_cast<float>(dk);
    return Vec3f{axisI_.x * a + axisJ_.x * b + axisK_.x * c, axisI_.y * a + axisJ_.y * b + axisK_.y * c,
                 axisI_.z * a + axisJ_.z * b + axisK_.z * c};
  }

  /// Calls f(first, last) for every run of consecutive vertex numbers that
  /// holds neighbours of v: the rows of the stencil's bounding block, cut
  /// to the image (they may include masked voxels and v itself).
  template <class F>
  STVD_ALWAYS_INLINE void forEachNeighborRun(VertexId v, F&& f) const {
    const VoxelIndex c = indexOf(v);
    const int r = stencil_.radius();
    const int iFirst = std::max(c.i - r, 0), iLast = std::min(c.i + r, static_cast<int>(nx_) - 1);
    const int jFirst = std::max(c.j - r, 0), jLast = std::min(c.j + r, static_cast<int>(ny_) - 1);
    const int kFirst = std::max(c.k - r, 0), kLast = std::min(c.k + r, static_cast<int>(nz_) - 1);
    for (int k = kFirst; k <= kLast; ++k)
      for (int j = jFirst; j <= jLast; ++j) f(vertexAtUnchecked(iFirst, j, k), vertexAtUnchecked(iLast, j, k));
  }

  /// Nothing to ask for ahead of forEachNeighbor: the edge vectors come from
  /// the stencil, which stays in cache.
  void prefetchNeighborGeometry(VertexId) const {}

  /// Calls f(w, e) for every neighbour w of the domain vertex v inside the
  /// domain whose stencil step from v lies in the domain (segmentInDomain), with e the
  /// physical edge vector x(w) - x(v). The interior of the image takes a
  /// path without bounds checks, and a voxel farther from every excluded
  /// voxel than the stencil reaches takes one without the steps' checks.
  template <class F>
  STVD_ALWAYS_INLINE void forEachNeighbor(VertexId v, F&& f) const {
    const VoxelIndex c = indexOf(v);
    const int r = stencil_.radius();
    const bool interior = c.i >= r && c.j >= r && c.k >= r && c.i + r < static_cast<int>(nx_) &&
                          c.j + r < static_cast<int>(ny_) && c.k + r < static_cast<int>(nz_);
    const int n = stencil_.size();
    const std::uint8_t* mask = mask_.empty() ? nullptr : mask_.data();
    // Near an excluded voxel a step must also keep to the domain's cells.
    const bool checkSteps = mask && clearance_[v] <= r;
    for (int s = 0; s < n; ++s) {
      if (!interior) {
        const auto& o = stencil_.offsets()[s];
        if (!isInsideImage(c.i + o[0], c.j + o[1], c.k + o[2])) continue;
      }
      const VertexId w = static_cast<VertexId>(static_cast<std::int64_t>(v) + linearOffset_[s]);
      if (mask && mask[w] == 0) continue;
      if (checkSteps && !stepSupportInDomain(v, s)) continue;
      f(w, edgeVector_[s]);
    }
  }

  /// Whether the straight segment between the centres of domain voxels a
  /// and b lies in the domain's region (see VoxelConnectivity): every point
  /// of it lies in a cell whose corners are all in the domain, i.e. every
  /// voxel that a trilinear interpolation at any point of the segment gives
  /// a non-zero weight is in the domain, or the piece passes through a
  /// contact that the connectivity joins. This is stricter than asking for
  /// every voxel whose cube the segment crosses. Always true without a mask;
  /// cheap when no excluded voxel lies within the segment's reach.
  bool segmentInDomain(VertexId a, VertexId b) const {
    if (mask_.empty()) return true;
    const VoxelIndex p = indexOf(a), q = indexOf(b);
    const int di = q.i - p.i, dj = q.j - p.j, dk = q.k - p.k;
    const int span = std::max({std::abs(di), std::abs(dj), std::abs(dk)});
    if (std::max(clearance_[a], clearance_[b]) > span) return true;
    if (span > kSegmentTableRadius) return traceSegmentSupport(p, q);
    constexpr int side = 2 * kSegmentTableRadius + 1;
    const int t = (di + kSegmentTableRadius) + side * ((dj + kSegmentTableRadius) + side * (dk + kSegmentTableRadius));
    for (std::uint32_t m = segmentSupportStart_[t]; m < segmentSupportStart_[t + 1]; ++m)
      if (mask_[static_cast<VertexId>(static_cast<std::int64_t>(a) + segmentSupportOffset_[m])] == 0) return false;
    return true;
  }

  /// Chebyshev distance, in voxels, from v to the nearest voxel of the
  /// image outside the domain, saturated at 255 (every voxel without a
  /// mask: empty). 0 for a voxel outside the domain.
  const std::vector<std::uint8_t>& clearance() const { return clearance_; }

 private:
  [[noreturn]] void throwIndexOutsideImage(int i, int j, int k) const;
  bool stepSupportInDomain(VertexId v, int s) const {
    for (std::uint32_t m = supportStart_[s]; m < supportStart_[s + 1]; ++m)
      if (mask_[static_cast<VertexId>(static_cast<std::int64_t>(v) + supportOffset_[m])] == 0) return false;
    return true;
  }
  bool traceSegmentSupport(const VoxelIndex& a, const VoxelIndex& b) const;
  void computeClearance();

  GridGeometry geometry_;
  Stencil stencil_;
  std::vector<std::uint8_t> mask_;
  VoxelConnectivity connectivity_ = VoxelConnectivity::Faces;
  std::vector<std::uint8_t> clearance_;
  // Per stencil offset s, the linear offsets (from v) of the voxels besides
  // v and w that its step needs in the domain:
  // supportOffset_[supportStart_[s] .. supportStart_[s + 1]).
  std::vector<std::uint32_t> supportStart_;
  std::vector<std::int64_t> supportOffset_;
  // The same per index offset d of a segment with |d|_inf up to
  // kSegmentTableRadius (STVD's candidates at k = 8 on the 26-neighbourhood
  // span at most 9 voxels), in x-fastest order over the block of offsets;
  // only when some voxel is excluded. Longer segments are walked.
  static constexpr int kSegmentTableRadius = 9;
  std::vector<std::uint32_t> segmentSupportStart_;
  std::vector<std::int64_t> segmentSupportOffset_;
  VertexId nx_ = 1, ny_ = 1, nz_ = 1, nxy_ = 1, vertexCount_ = 0, domainVertexCount_ = 0;
  detail::FixedDivisor rowDivisor_, sliceDivisor_;
  std::vector<std::int64_t> linearOffset_;
  std::vector<Vec3f> edgeVector_;
  Vec3f axisI_, axisJ_, axisK_;  // the physical vector of one index step along i, j, k
};

}  // namespace stvd
