// Lanthier's method over a voxel grid: the Steiner-point layout over the
// cells of the domain's region (complete cubes and the edges between domain
// voxels, and where the domain is thin its complete squares and joined
// contact diagonals), their points numbered per voxel, and the propagation
// over them.
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "stvd/propagation/detail/front_queue.hpp"
#include "voxel_grid/voxel_grid_steiner_cells.hpp"

namespace stvd::detail {
namespace {

using Index = std::array<int, 3>;

Index unit(int axis) {
  Index e{0, 0, 0};
  e[axis] = 1;
  return e;
}

Index operator+(Index a, const Index& b) {
  for (int axis = 0; axis < 3; ++axis) a[axis] += b[axis];
  return a;
}

Index operator-(Index a, const Index& b) {
  for (int axis = 0; axis < 3; ++axis) a[axis] -= b[axis];
  return a;
}

Vec3d toVec(const Index& d) { return {double(d[0]), double(d[1]), double(d[2])}; }

/// The two axes other than a, in increasing order.
void otherAxes(int a, int& b, int& c) {
  b = a == 0 ? 1 : 0;
  c = a == 2 ? 1 : 2;
}

}  // namespace

GridSteinerCells::GridSteinerCells(const VoxelGridDomain& domain, int steinerPoints)
    : GridSteinerCells(domain, steinerPoints, nullptr) {}

GridSteinerCells::GridSteinerCells(const VoxelGridDomain& domain, int steinerPoints, SetupProgress& setup)
    : GridSteinerCells(domain, steinerPoints, &setup) {}

bool GridSteinerCells::thinCellsPossible(const VoxelGridDomain& domain) {
  const GridGeometry& g = domain.geometry();
  return domain.hasMask() || g.size[0] < 2 || g.size[1] < 2 || g.size[2] < 2;
}

std::uint64_t GridSteinerCells::setupSteps(const VoxelGridDomain& domain) {
  const bool masked = domain.domainVertexCount() < domain.vertexCount();
  // The numbering and the bases near the domain (masked only), the cubes
  // and edges, and where thin cells are possible the squares, the cells
  // that depend on them and the final flags.
  const std::uint64_t passes = (masked ? 2 : 0) + 1 + (thinCellsPossible(domain) ? 3 : 0);
  return passes * domain.vertexCount();
}

GridSteinerCells::GridSteinerCells(const VoxelGridDomain& domain, int steinerPoints, SetupProgress* setup)
    : domain_(domain), m_(steinerPoints) {
  const std::uint64_t slots = lanthierGridPointCount(1, m_);
  if (domain.domainVertexCount() < domain.vertexCount()) {
    numberOfVoxel_.assign(domain.vertexCount(), kNoVertex);
    voxelOfNumber_.reserve(domain.domainVertexCount());
    for (VertexId v = 0; v < domain.vertexCount(); ++v) {
      if (setup) setup->step();
      if (domain.contains(v)) {
        numberOfVoxel_[v] = static_cast<std::uint32_t>(voxelOfNumber_.size());
        voxelOfNumber_.push_back(v);
      }
    }
  }
  pointCount_ = slots * domain.domainVertexCount();
  if (pointCount_ >= FrontQueue::kFinal)
    throw std::invalid_argument("Steiner graph of " + std::to_string(pointCount_) +
                                " points is too large for 32-bit indices; use fewer Steiner points or a smaller grid");
  slots_ = static_cast<std::uint32_t>(slots);
  slotDivisor_ = FixedDivisor(slots_);
  buildShapes();
  id_.resize(shapes_[kCube].position.size());
  if (setup) findCells(*setup);
}

void GridSteinerCells::buildShapes() {
  const GridGeometry& g = domain_.geometry();
  const VertexId nx = static_cast<VertexId>(g.size[0]), ny = static_cast<VertexId>(g.size[1]);
  const double step = 1.0 / (m_ + 1);
  slotIndexOffset_.assign(slots_, Vec3d{});
  around_.assign(slots_, {});
  cubesAndEdgesAround_.assign(slots_, 0);

  auto setCorners = [&](int s, std::initializer_list<Index> corners) {
    Shape& shape = shapes_[s];
    for (const Index& d : corners) {
      shape.cornerIndex[shape.cornerCount] = d;
      shape.cornerOffset[shape.cornerCount] = static_cast<VertexId>(d[0]) + nx * (d[1] + ny * d[2]);
      ++shape.cornerCount;
    }
  };
  // The point of slot `slot` at the cell's corner voxel d, at the continuous
  // index offset inCell from the base voxel.
  auto addPoint = [&](int s, const Index& d, std::uint32_t slot, Vec3d inCell) {
    Shape& shape = shapes_[s];
    int corner = 0;
    while (shape.cornerIndex[corner] != d) ++corner;  // every point is numbered at a corner of its cell
    const int local = static_cast<int>(shape.position.size());
    shape.position.push_back(toFloat(g.indexToPhysicalOffset(inCell.x, inCell.y, inCell.z)));
    shape.pointCorner.push_back(static_cast<std::uint8_t>(corner));
    shape.pointSlot.push_back(slot);
    slotIndexOffset_[slot] = inCell - toVec(d);
    // The cube and the edges are built first, so their incidences come first.
    around_[slot].push_back({d, 1u << s, s, local});
    if (s == kCube || (s >= kEdge && s < kEdge + 3)) ++cubesAndEdgesAround_[slot];
  };
  auto addCornerPoints = [&](int s) {
    const Shape& shape = shapes_[s];
    for (int corner = 0; corner < shape.cornerCount; ++corner)
      addPoint(s, shape.cornerIndex[corner], 0, toVec(shape.cornerIndex[corner]));
  };
  // The M points of the grid edge from corner `from` along axis a.
  auto addEdgePoints = [&](int s, const Index& from, int a) {
    for (int m = 1; m <= m_; ++m) {
      Vec3d x = toVec(from);
      (a == 0 ? x.x : a == 1 ? x.y : x.z) += m * step;
      addPoint(s, from, 1 + a * m_ + (m - 1), x);
    }
  };
  // The M x M points inside the square at corner `at` normal to axis a.
  auto addFacePoints = [&](int s, const Index& at, int a) {
    int b, c;
    otherAxes(a, b, c);
    for (int mb = 1; mb <= m_; ++mb)
      for (int mc = 1; mc <= m_; ++mc) {
        double x[3] = {double(at[0]), double(at[1]), double(at[2])};
        x[b] += mb * step;
        x[c] += mc * step;
        addPoint(s, at, 1 + 3 * m_ + a * m_ * m_ + (mb - 1) * m_ + (mc - 1), {x[0], x[1], x[2]});
      }
  };

  // The cube: corner n at (n & 1, n >> 1 & 1, n >> 2 & 1); then per axis a
  // its four edges along a and its two faces normal to a.
  setCorners(kCube, {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}});
  addCornerPoints(kCube);
  for (int a = 0; a < 3; ++a) {
    int b, c;
    otherAxes(a, b, c);
    for (int db = 0; db < 2; ++db)
      for (int dc = 0; dc < 2; ++dc) {
        Index d{0, 0, 0};
        d[b] = db;
        d[c] = dc;
        addEdgePoints(kCube, d, a);
      }
    for (int da = 0; da < 2; ++da) {
      Index d{0, 0, 0};
      d[a] = da;
      addFacePoints(kCube, d, a);
    }
  }
  const Index origin{0, 0, 0};
  for (int a = 0; a < 3; ++a) {  // the edge along a
    setCorners(kEdge + a, {origin, unit(a)});
    addCornerPoints(kEdge + a);
    addEdgePoints(kEdge + a, origin, a);
  }
  for (int a = 0; a < 3; ++a) {
    int b, c;
    otherAxes(a, b, c);
    const Index eb = unit(b), ec = unit(c);
    // The square normal to a: its corners, the points on its four edges and
    // those inside it.
    const int square = kSquare + a;
    setCorners(square, {origin, eb, ec, eb + ec});
    addCornerPoints(square);
    addEdgePoints(square, origin, b);
    addEdgePoints(square, ec, b);
    addEdgePoints(square, origin, c);
    addEdgePoints(square, eb, c);
    addFacePoints(square, origin, a);
    // Its two diagonals.
    setCorners(kFaceDiagonal + 2 * a, {origin, eb + ec});
    setCorners(kFaceDiagonal + 2 * a + 1, {eb, ec});
    addCornerPoints(kFaceDiagonal + 2 * a);
    addCornerPoints(kFaceDiagonal + 2 * a + 1);
  }
  for (int n = 0; n < 4; ++n) {
    const int opposite = 7 - n;
    setCorners(kBodyDiagonal + n,
               {{n & 1, (n >> 1) & 1, (n >> 2) & 1}, {opposite & 1, (opposite >> 1) & 1, (opposite >> 2) & 1}});
    addCornerPoints(kBodyDiagonal + n);
  }
}

void GridSteinerCells::findCells(SetupProgress& setup) {
  const GridGeometry& g = domain_.geometry();
  const int size[3] = {static_cast<int>(g.size[0]), static_cast<int>(g.size[1]), static_cast<int>(g.size[2])};
  flags_.assign(domain_.vertexCount(), 0);
  auto inDomain = [&](const Index& p) {
    return domain_.isInsideImage(p[0], p[1], p[2]) && domain_.contains(domain_.vertexAtUnchecked(p[0], p[1], p[2]));
  };
  auto complete = [&](const Index& base, int s) {
    const Shape& shape = shapes_[s];
    for (int corner = 0; corner < shape.cornerCount; ++corner)
      if (!inDomain(base + shape.cornerIndex[corner])) return false;
    return true;
  };
  // Every cell has a domain voxel among the eight of the block at its base:
  // the bases of a brain's background are skipped.
  std::vector<std::uint8_t> nearDomain;
  if (domain_.domainVertexCount() < domain_.vertexCount()) {
    nearDomain.assign(domain_.vertexCount(), 0);
    for (VertexId v = 0; v < domain_.vertexCount(); ++v) {
      setup.step();
      if (!domain_.contains(v)) continue;
      const VoxelIndex c = domain_.indexOf(v);
      for (int n = 0; n < 8; ++n) {
        const int i = c.i - (n & 1), j = c.j - ((n >> 1) & 1), k = c.k - ((n >> 2) & 1);
        if (i >= 0 && j >= 0 && k >= 0) nearDomain[domain_.vertexAtUnchecked(i, j, k)] = 1;
      }
    }
  }
  auto forEachBase = [&](auto&& visit) {
    for (int k = 0; k < size[2]; ++k)
      for (int j = 0; j < size[1]; ++j)
        for (int i = 0; i < size[0]; ++i) {
          setup.step();
          const VertexId v = domain_.vertexAtUnchecked(i, j, k);
          if (nearDomain.empty() || nearDomain[v]) visit(Index{i, j, k}, v);
        }
  };
  forEachBase([&](const Index& p, VertexId v) {
    if (complete(p, kCube)) flags_[v] |= 1u << kCube;
    for (int a = 0; a < 3; ++a)
      if (complete(p, kEdge + a)) flags_[v] |= 1u << (kEdge + a);
  });
  if (!thinCellsPossible(domain_)) return;

  // Complete squares first (kept in their bits for now, whether or not a
  // complete cube holds them), then what depends on them.
  forEachBase([&](const Index& p, VertexId v) {
    for (int a = 0; a < 3; ++a)
      if (complete(p, kSquare + a)) flags_[v] |= 1u << (kSquare + a);
  });
  auto has = [&](const Index& p, int s) {
    return domain_.isInsideImage(p[0], p[1], p[2]) &&
           (flags_[domain_.vertexAtUnchecked(p[0], p[1], p[2])] & (1u << s)) != 0;
  };
  const VoxelConnectivity connectivity = domain_.connectivity();
  std::vector<std::uint32_t> lower(domain_.vertexCount(), 0);
  forEachBase([&](const Index& p, VertexId v) {
    for (int a = 0; a < 3; ++a) {
      // A complete square in no complete cube (those at p and p - e_a).
      if (has(p, kSquare + a) && !has(p, kCube) && !has(p - unit(a), kCube)) lower[v] |= 1u << (kSquare + a);
      // An edge contact: a diagonal of an incomplete square.
      if (connectivity != VoxelConnectivity::Faces && !has(p, kSquare + a))
        for (int q = 0; q < 2; ++q)
          if (complete(p, kFaceDiagonal + 2 * a + q)) lower[v] |= 1u << (kFaceDiagonal + 2 * a + q);
    }
    // A corner contact: a diagonal of an incomplete cube inside the image.
    if (connectivity == VoxelConnectivity::Corners && !has(p, kCube) && p[0] + 1 < size[0] &&
        p[1] + 1 < size[1] && p[2] + 1 < size[2])
      for (int n = 0; n < 4; ++n)
        if (complete(p, kBodyDiagonal + n)) lower[v] |= 1u << (kBodyDiagonal + n);
  });
  const std::uint32_t cubeAndEdges = (1u << kCube) | (7u << kEdge);
  for (VertexId v = 0; v < domain_.vertexCount(); ++v) {
    setup.step();
    flags_[v] = (flags_[v] & cubeAndEdges) | lower[v];
    hasThinCells_ = hasThinCells_ || lower[v] != 0;
  }
}

Vec3d GridSteinerCells::position(SteinerPointId p) const {
  const std::uint32_t n = slotDivisor_.divide(p);
  const VoxelIndex c = domain_.indexOf(voxelOf(n));
  const Vec3d o = slotIndexOffset_[p - n * slots_];
  return domain_.geometry().indexToPhysicalPoint(c.i + o.x, c.j + o.y, c.k + o.z);
}

}  // namespace stvd::detail

namespace stvd {

template <class Norm>
LanthierResult lanthierPropagate(const VoxelGridDomain& domain, const MetricField<Norm>& metric,
                                          const std::vector<VertexId>& sources, const LanthierOptions& options) {
  detail::validate(domain, domain.vertexCount(), metric, sources, options);
  return detail::setUpAndRunLanthier<detail::GridSteinerCells>(
      metric, domain.vertexCount(), domain.domainVertexCount(), sources, options,
      detail::GridSteinerCells::setupSteps(domain),
      lanthierGridPointCount(domain.domainVertexCount(), options.steinerPoints), domain, options.steinerPoints);
}

Vec3d steinerPointPosition(const VoxelGridDomain& domain, int steinerPoints, SteinerPointId p) {
  const detail::GridSteinerCells cells(domain, steinerPoints);
  if (p >= cells.pointCount()) throw std::invalid_argument("Steiner point " + std::to_string(p) + " out of range");
  return cells.position(p);
}

template LanthierResult lanthierPropagate(const VoxelGridDomain&, const RiemannianMetric&,
                                                   const std::vector<VertexId>&, const LanthierOptions&);
template LanthierResult lanthierPropagate(const VoxelGridDomain&, const RandersMetric&,
                                                   const std::vector<VertexId>&, const LanthierOptions&);
// Tabulated (Finsler) norms: the FOD metrics of the imaging adapter (docs/fod.md).
template LanthierResult lanthierPropagate(const VoxelGridDomain&, const MetricField<LatticeTableNorm<2>>&,
                                          const std::vector<VertexId>&, const LanthierOptions&);

std::uint64_t lanthierGridPointCount(std::uint64_t domainVoxelCount, int steinerPoints) {
  const std::uint64_t m = static_cast<std::uint64_t>(steinerPoints);
  return (1 + 3 * m + 3 * m * m) * domainVoxelCount;
}

}  // namespace stvd
