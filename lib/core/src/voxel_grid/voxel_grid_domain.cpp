#include "stvd/voxel_grid/voxel_grid_domain.hpp"

#include <algorithm>
#include <array>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace stvd {
namespace {

using Index3 = std::array<std::int64_t, 3>;

std::int64_t floorDivide(std::int64_t a, std::int64_t b) {  // b > 0
  const std::int64_t q = a / b;
  return (a % b != 0 && a < 0) ? q - 1 : q;
}

/// Walks the straight segment from the integer point a to a + d through
/// the cells of the integer lattice. The segment is cut where any of its
/// coordinates crosses an integer; on each open piece between two cuts the
/// coordinates that change lie strictly between two integers and the others
/// are integers, so the voxels a trilinear interpolation gives non-zero
/// weight are the same along the whole piece: the 2^m corners of the
/// m-dimensional cell (m moving axes) that holds it. `piece(corners, count,
/// from, to)` is called once per piece with those corners and the piece's
/// end points in units of 1/2L of an index (L the least common multiple of
/// the moving |d|), and may stop the walk by returning false. Returns false
/// when it was stopped.
template <class Piece>
bool walkSegmentCells(const Index3& a, const Index3& d, Piece&& piece) {
  std::int64_t lcm = 1;
  for (int axis = 0; axis < 3; ++axis)
    if (d[axis] != 0) lcm = std::lcm(lcm, std::abs(d[axis]));
  // Cut parameters in units of 1/lcm of the segment: multiples of lcm/|d|.
  // The segments of stencils and STVD chains span a few dozen voxels at
  // most; longer ones take a buffer on the heap.
  constexpr std::int64_t kStackCuts = 256;
  const std::int64_t cutCapacity = std::abs(d[0]) + std::abs(d[1]) + std::abs(d[2]) + 2;
  std::int64_t stackCuts[kStackCuts];
  std::vector<std::int64_t> heapCuts;
  if (cutCapacity > kStackCuts) heapCuts.resize(static_cast<std::size_t>(cutCapacity));
  std::int64_t* cuts = cutCapacity > kStackCuts ? heapCuts.data() : stackCuts;
  int cutCount = 0;
  cuts[cutCount++] = 0;
  for (int axis = 0; axis < 3; ++axis) {
    const std::int64_t n = std::abs(d[axis]);
    for (std::int64_t j = 1; j < n; ++j) cuts[cutCount++] = j * (lcm / n);
  }
  cuts[cutCount++] = lcm;
  std::sort(cuts, cuts + cutCount);
  cutCount = static_cast<int>(std::unique(cuts, cuts + cutCount) - cuts);
  for (int c = 0; c + 1 < cutCount; ++c) {
    // Midpoint of the piece, as a point with denominator 2 lcm.
    const std::int64_t t2 = cuts[c] + cuts[c + 1];
    std::int64_t low[3];
    bool moving[3];
    for (int axis = 0; axis < 3; ++axis) {
      const std::int64_t numerator = 2 * lcm * a[axis] + t2 * d[axis];
      low[axis] = floorDivide(numerator, 2 * lcm);
      moving[axis] = numerator != low[axis] * 2 * lcm;
    }
    Index3 corners[8];
    int count = 0;
    for (int n = 0; n < 8; ++n) {
      if (((n & 1) && !moving[0]) || ((n & 2) && !moving[1]) || ((n & 4) && !moving[2])) continue;
      corners[count++] = {low[0] + (n & 1 ? 1 : 0), low[1] + (n & 2 ? 1 : 0), low[2] + (n & 4 ? 1 : 0)};
    }
    Index3 from, to;
    for (int axis = 0; axis < 3; ++axis) {
      from[axis] = 2 * lcm * a[axis] + 2 * cuts[c] * d[axis];
      to[axis] = 2 * lcm * a[axis] + 2 * cuts[c + 1] * d[axis];
    }
    if (!piece(corners, count, from, to, 2 * lcm)) return false;
  }
  return true;
}

/// Whether a piece of a segment (end points in units of 1/denominator) is a
/// contact diagonal that `connectivity` joins: it runs from one voxel centre
/// to a diagonal neighbour across a square (Edges) or a cube (Corners).
bool isJoinedContact(const Index3& from, const Index3& to, std::int64_t denominator,
                     VoxelConnectivity connectivity) {
  if (connectivity == VoxelConnectivity::Faces) return false;
  int diagonalAxes = 0;
  for (int axis = 0; axis < 3; ++axis) {
    if (from[axis] % denominator != 0 || to[axis] % denominator != 0) return false;
    const std::int64_t step = std::abs(to[axis] - from[axis]) / denominator;
    if (step > 1) return false;
    diagonalAxes += static_cast<int>(step);
  }
  return diagonalAxes == 2 || (diagonalAxes == 3 && connectivity == VoxelConnectivity::Corners);
}

/// The linear offsets (from a) of the voxels that the segment from a to
/// a + d needs in the domain besides a and a + d (VoxelGridDomain::
/// segmentInDomain): the corners of every cell it passes through, or, for a
/// piece on a contact that `connectivity` joins, the piece's two ends.
/// Sorted, without repeats.
std::vector<std::int64_t> segmentSupport(const Index3& d, VoxelConnectivity connectivity, std::int64_t nx,
                                         std::int64_t ny) {
  std::vector<std::int64_t> needed;
  auto add = [&](const Index3& q) {
    const bool end = (q[0] == 0 && q[1] == 0 && q[2] == 0) || (q[0] == d[0] && q[1] == d[1] && q[2] == d[2]);
    if (!end) needed.push_back(q[0] + nx * (q[1] + ny * q[2]));
  };
  walkSegmentCells({0, 0, 0}, d,
                   [&](const Index3* corners, int count, const Index3& from, const Index3& to,
                       std::int64_t denominator) {
                     if (isJoinedContact(from, to, denominator, connectivity)) {
                       add({from[0] / denominator, from[1] / denominator, from[2] / denominator});
                       add({to[0] / denominator, to[1] / denominator, to[2] / denominator});
                     } else {
                       for (int c = 0; c < count; ++c) add(corners[c]);
                     }
                     return true;
                   });
  std::sort(needed.begin(), needed.end());
  needed.erase(std::unique(needed.begin(), needed.end()), needed.end());
  return needed;
}

}  // namespace

void VoxelGridDomain::throwIndexOutsideImage(int i, int j, int k) const {
  throw std::out_of_range("voxel index (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
                          ") is outside the image of " + std::to_string(nx_) + " x " + std::to_string(ny_) + " x " +
                          std::to_string(nz_) + " voxels");
}

VoxelGridDomain::VoxelGridDomain(const GridGeometry& geometry, Stencil stencil,
                                 std::vector<std::uint8_t> mask, VoxelConnectivity connectivity)
    : geometry_(geometry), stencil_(std::move(stencil)), mask_(std::move(mask)), connectivity_(connectivity) {
  geometry_.validate();
  nx_ = static_cast<VertexId>(geometry_.size[0]);
  ny_ = static_cast<VertexId>(geometry_.size[1]);
  nz_ = static_cast<VertexId>(geometry_.size[2]);
  nxy_ = nx_ * ny_;
  vertexCount_ = static_cast<VertexId>(geometry_.voxelCount());
  rowDivisor_ = detail::FixedDivisor(nx_);
  sliceDivisor_ = detail::FixedDivisor(nxy_);
  if (!mask_.empty() && mask_.size() != vertexCount_)
    throw std::invalid_argument("mask has " + std::to_string(mask_.size()) +
                                " voxels but the grid has " + std::to_string(vertexCount_));
  if (connectivity_ != VoxelConnectivity::Faces && connectivity_ != VoxelConnectivity::Edges &&
      connectivity_ != VoxelConnectivity::Corners)
    throw std::invalid_argument("voxel connectivity must be 6, 18 or 26");
  domainVertexCount_ = vertexCount_;
  if (!mask_.empty()) {
    domainVertexCount_ = 0;
    for (std::uint8_t m : mask_) domainVertexCount_ += m != 0 ? 1 : 0;
  }
  axisI_ = toFloat(geometry_.indexToPhysicalOffset(1, 0, 0));
  axisJ_ = toFloat(geometry_.indexToPhysicalOffset(0, 1, 0));
  axisK_ = toFloat(geometry_.indexToPhysicalOffset(0, 0, 1));
  supportStart_.push_back(0);
  for (const auto& o : stencil_.offsets()) {
    linearOffset_.push_back(o[0] + static_cast<std::int64_t>(nx_) * (o[1] + static_cast<std::int64_t>(ny_) * o[2]));
    edgeVector_.push_back(toFloat(geometry_.indexToPhysicalOffset(o[0], o[1], o[2])));
    // The voxels (besides both ends) that the step's segment needs.
    const std::vector<std::int64_t> needed = segmentSupport({o[0], o[1], o[2]}, connectivity_, nx_, ny_);
    supportOffset_.insert(supportOffset_.end(), needed.begin(), needed.end());
    supportStart_.push_back(static_cast<std::uint32_t>(supportOffset_.size()));
  }
  if (!mask_.empty() && domainVertexCount_ < vertexCount_) {
    computeClearance();
    // The same for every index offset of the segments that STVD's
    // candidates test: a lookup instead of a walk through the cells.
    // The second half of the block holds the reversed segments of the
    // first: the same voxels, seen from the other end.
    constexpr int r = kSegmentTableRadius, side = 2 * r + 1, offsets = side * side * side;
    segmentSupportStart_.reserve(offsets + 1);
    segmentSupportStart_.push_back(0);
    int t = 0;
    for (int k = -r; k <= r; ++k)
      for (int j = -r; j <= r; ++j)
        for (int i = -r; i <= r; ++i, ++t) {
          if (t <= offsets / 2) {
            const std::vector<std::int64_t> needed = segmentSupport({i, j, k}, connectivity_, nx_, ny_);
            segmentSupportOffset_.insert(segmentSupportOffset_.end(), needed.begin(), needed.end());
          } else {
            const int reversed = offsets - 1 - t;  // the table index of -d
            const std::int64_t d = i + static_cast<std::int64_t>(nx_) * (j + static_cast<std::int64_t>(ny_) * k);
            for (std::uint32_t m = segmentSupportStart_[reversed]; m < segmentSupportStart_[reversed + 1]; ++m)
              segmentSupportOffset_.push_back(segmentSupportOffset_[m] + d);
          }
          segmentSupportStart_.push_back(static_cast<std::uint32_t>(segmentSupportOffset_.size()));
        }
  } else if (!mask_.empty()) {
    computeClearance();  // 255 everywhere
  }
}

// Chebyshev distance to the nearest excluded voxel: the length of the
// shortest 26-connected lattice path to it, which a forward and a backward
// raster pass over the 13 neighbours already visited compute exactly.
void VoxelGridDomain::computeClearance() {
  constexpr int kFar = 255;
  clearance_.assign(vertexCount_, kFar);
  // A mask that keeps every voxel (the tool always passes one) needs no
  // passes: they cost as much as a Dijkstra propagation of the grid.
  if (domainVertexCount_ == vertexCount_) return;
  for (VertexId v = 0; v < vertexCount_; ++v)
    if (mask_[v] == 0) clearance_[v] = 0;
  // The neighbours that precede a voxel in raster order (k, then j, then i).
  std::array<std::array<int, 3>, 13> before;
  int count = 0;
  for (int dk = -1; dk <= 0; ++dk)
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di)
        if (dk < 0 || dj < 0 || (dj == 0 && di < 0)) before[count++] = {di, dj, dk};
  const int n[3] = {static_cast<int>(nx_), static_cast<int>(ny_), static_cast<int>(nz_)};
  for (const int sign : {1, -1}) {
    for (VertexId step = 0; step < vertexCount_; ++step) {
      const VertexId v = sign > 0 ? step : vertexCount_ - 1 - step;
      if (clearance_[v] == 0) continue;
      const VoxelIndex c = indexOf(v);
      int best = clearance_[v];
      for (const auto& o : before) {
        const int i = c.i + sign * o[0], j = c.j + sign * o[1], k = c.k + sign * o[2];
        if (i < 0 || j < 0 || k < 0 || i >= n[0] || j >= n[1] || k >= n[2]) continue;
        best = std::min(best, clearance_[vertexAtUnchecked(i, j, k)] + 1);
      }
      clearance_[v] = static_cast<std::uint8_t>(best);
    }
  }
}

bool VoxelGridDomain::traceSegmentSupport(const VoxelIndex& a, const VoxelIndex& b) const {
  const Index3 start{a.i, a.j, a.k};
  const Index3 d{b.i - a.i, b.j - a.j, b.k - a.k};
  return walkSegmentCells(start, d,
                          [&](const Index3* corners, int count, const Index3& from, const Index3& to,
                              std::int64_t denominator) {
                            if (isJoinedContact(from, to, denominator, connectivity_)) {
                              // Both ends are voxel centres; they must be in the domain.
                              return contains(vertexAtUnchecked(static_cast<int>(from[0] / denominator),
                                                       static_cast<int>(from[1] / denominator),
                                                       static_cast<int>(from[2] / denominator))) &&
                                     contains(vertexAtUnchecked(static_cast<int>(to[0] / denominator),
                                                       static_cast<int>(to[1] / denominator),
                                                       static_cast<int>(to[2] / denominator)));
                            }
                            for (int c = 0; c < count; ++c) {
                              const Index3& q = corners[c];
                              if (mask_[vertexAtUnchecked(static_cast<int>(q[0]), static_cast<int>(q[1]),
                                                 static_cast<int>(q[2]))] == 0)
                                return false;
                            }
                            return true;
                          });
}

}  // namespace stvd
