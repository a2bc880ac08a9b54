#include "stvd/cell_mesh/tetrahedral_region.hpp"

#include <cmath>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace stvd {
namespace {

bool hasCorner(const TetrahedralRegion::Tetrahedron& t, VertexId v) {
  return t[0] == v || t[1] == v || t[2] == v || t[3] == v;
}

/// Squared Euclidean distance transform along one line of n cells
/// (Felzenszwalb and Huttenlocher, "Distance transforms of sampled
/// functions", 2012): d[q] = min over p of (q - p)^2 + f[p].
void distanceTransformLine(const double* f, std::size_t n, double* d, std::vector<std::size_t>& parabola,
                           std::vector<double>& boundary) {
  parabola.resize(n);
  boundary.resize(n + 1);
  std::size_t k = 0;
  parabola[0] = 0;
  boundary[0] = -std::numeric_limits<double>::infinity();
  boundary[1] = std::numeric_limits<double>::infinity();
  auto intersection = [&](std::size_t q, std::size_t p) {
    const double qd = static_cast<double>(q), pd = static_cast<double>(p);
    return ((f[q] + qd * qd) - (f[p] + pd * pd)) / (2.0 * qd - 2.0 * pd);
  };
  for (std::size_t q = 1; q < n; ++q) {
    double x = intersection(q, parabola[k]);
    while (x <= boundary[k]) {
      --k;
      x = intersection(q, parabola[k]);
    }
    ++k;
    parabola[k] = q;
    boundary[k] = x;
    boundary[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (std::size_t q = 0; q < n; ++q) {
    while (boundary[k + 1] < static_cast<double>(q)) ++k;
    const double offset = static_cast<double>(q) - static_cast<double>(parabola[k]);
    d[q] = offset * offset + f[parabola[k]];
  }
}

}  // namespace

TetrahedralRegion::TetrahedralRegion(const std::vector<Vec3d>& points, std::vector<Tetrahedron> tets) {
  if (tets.size() >= kNoTetrahedron)
    throw std::invalid_argument("mesh has too many tetrahedra for 32-bit indices");
  // Numbered by their smallest corner, so that the tetrahedra a walk visits
  // lie about as close in memory as their corners' numbers: in the order
  // TetGen writes them they are scattered, and a walk took 4 times longer
  // (a Morton vertex order, as `stvd distance` uses, then keeps a walk's
  // records in a few pages).
  std::stable_sort(tets.begin(), tets.end(), [](const Tetrahedron& a, const Tetrahedron& b) {
    return *std::min_element(a.begin(), a.end()) < *std::min_element(b.begin(), b.end());
  });
  cells_.resize(tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t)
    cells_[t] = {tets[t], {kNoTetrahedron, kNoTetrahedron, kNoTetrahedron, kNoTetrahedron}};
  tets = {};
  // The tetrahedra around each vertex, in increasing order.
  firstAround_.assign(points.size() + 1, 0);
  for (const Cell& cell : cells_)
    for (VertexId v : cell.corner) ++firstAround_[v + 1];
  std::partial_sum(firstAround_.begin(), firstAround_.end(), firstAround_.begin());
  around_.resize(4 * cells_.size());
  std::vector<std::uint64_t> next(firstAround_.begin(), firstAround_.end() - 1);
  for (std::size_t t = 0; t < cells_.size(); ++t)
    for (VertexId v : cells_[t].corner) around_[next[v]++] = static_cast<std::uint32_t>(t);
  findNeighbors(points);
  measureClearance(points);
}

// The tetrahedron across a face is found among those around one of its
// corners: the one other than t that has the two other corners too.
void TetrahedralRegion::findNeighbors(const std::vector<Vec3d>& points) {
  for (std::size_t t = 0; t < cells_.size(); ++t) {
    const Tetrahedron& c = cells_[t].corner;
    for (int f = 0; f < 4; ++f) {
      if (cells_[t].neighbor[f] != kNoTetrahedron) continue;
      const VertexId a = c[(f + 1) % 4], b = c[(f + 2) % 4], d = c[(f + 3) % 4];
      int found = 0;
      for (const std::uint32_t* u = tetrahedraAroundBegin(a); u != tetrahedraAroundEnd(a); ++u) {
        if (*u == t || !hasCorner(cells_[*u].corner, b) || !hasCorner(cells_[*u].corner, d)) continue;
        if (++found > 1) {
          // Positions rather than vertex numbers, in lexicographic order:
          // the same in every numbering of the mesh's vertices.
          std::array<Vec3d, 3> corners{points[a], points[b], points[d]};
          std::sort(corners.begin(), corners.end(), [](Vec3d p, Vec3d q) {
            return p.x != q.x ? p.x < q.x : p.y != q.y ? p.y < q.y : p.z < q.z;
          });
          std::ostringstream message;
          message << "the face with corners at";
          for (int k = 0; k < 3; ++k)
            message << (k == 0 ? " (" : ", (") << corners[k].x << ", " << corners[k].y << ", " << corners[k].z << ")";
          message << " belongs to more than two tetrahedra";
          throw std::invalid_argument(message.str());
        }
        cells_[t].neighbor[f] = *u;
        const Tetrahedron& o = cells_[*u].corner;
        for (int g = 0; g < 4; ++g)
          if (o[g] != a && o[g] != b && o[g] != d) cells_[*u].neighbor[g] = static_cast<std::uint32_t>(t);
      }
    }
  }
}

// The places where the region is not convex, and a lower bound on every
// vertex's distance to them from a Euclidean distance transform on a
// coarse grid of cells: a vertex whose cell lies D cells (centre to centre)
// from the nearest cell such a place touches is at least (D - sqrt 3) cell
// widths from it.
void TetrahedralRegion::measureClearance(const std::vector<Vec3d>& points) {
  // Boundary faces with their outward unit normals.
  struct BoundaryFace {
    VertexId corner[3];
    Vec3d outward;
  };
  std::vector<BoundaryFace> faces;
  for (std::size_t t = 0; t < cells_.size(); ++t)
    for (int f = 0; f < 4; ++f) {
      if (cells_[t].neighbor[f] != kNoTetrahedron) continue;
      const Tetrahedron& c = cells_[t].corner;
      BoundaryFace face{{c[(f + 1) % 4], c[(f + 2) % 4], c[(f + 3) % 4]}, {}};
      const Vec3d a = points[face.corner[0]];
      Vec3d n = cross(points[face.corner[1]] - a, points[face.corner[2]] - a);
      if (dot(n, points[c[f]] - a) > 0.0) n = -1.0 * n;
      const double length = norm(n);
      face.outward = length > 0.0 ? (1.0 / length) * n : Vec3d{};
      faces.push_back(face);
    }

  // Boundary edges: (low corner, high corner, face, the face's third corner).
  struct EdgeOfFace {
    VertexId low, high;
    std::uint32_t face;
    VertexId third;
  };
  std::vector<EdgeOfFace> edges;
  edges.reserve(3 * faces.size());
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (int e = 0; e < 3; ++e) {
      const VertexId a = faces[f].corner[e], b = faces[f].corner[(e + 1) % 3], third = faces[f].corner[(e + 2) % 3];
      edges.push_back({std::min(a, b), std::max(a, b), static_cast<std::uint32_t>(f), third});
    }
  auto byEdge = [](const EdgeOfFace& x, const EdgeOfFace& y) {
    return x.low != y.low ? x.low < y.low : x.high != y.high ? x.high < y.high : x.face < y.face;
  };
  std::sort(edges.begin(), edges.end(), byEdge);
  std::vector<std::array<Vec3d, 2>> featureSegments;
  for (std::size_t first = 0, last; first < edges.size(); first = last) {
    last = first + 1;
    while (last < edges.size() && edges[last].low == edges[first].low && edges[last].high == edges[first].high) ++last;
    const Vec3d a = points[edges[first].low];
    bool convex = last - first == 2;
    if (convex) {
      // Two boundary faces meet at the edge: the region there is a wedge,
      // convex when neither face's third corner lies outside the other's
      // plane (a flat pair of faces is convex).
      for (int side = 0; side < 2 && convex; ++side) {
        const EdgeOfFace& mine = edges[first + side];
        const EdgeOfFace& other = edges[first + 1 - side];
        const Vec3d r = points[other.third] - a;
        if (dot(faces[mine.face].outward, r) > 1e-9 * norm(r)) convex = false;
      }
    }
    if (!convex) {
      ++nonConvexEdges_;
      featureSegments.push_back({a, points[edges[first].high]});
    }
  }

  // Boundary vertices whose boundary faces do not form one fan, joined
  // through shared boundary edges: separate parts touch there.
  std::vector<std::pair<VertexId, std::uint32_t>> vertexFaces;
  for (std::size_t f = 0; f < faces.size(); ++f)
    for (VertexId v : faces[f].corner) vertexFaces.emplace_back(v, static_cast<std::uint32_t>(f));
  std::sort(vertexFaces.begin(), vertexFaces.end());
  std::vector<Vec3d> featurePoints;
  std::vector<std::uint32_t> local, parent;
  std::vector<std::pair<VertexId, std::uint32_t>> spokes;  // (other corner, local face)
  for (std::size_t first = 0, last; first < vertexFaces.size(); first = last) {
    const VertexId v = vertexFaces[first].first;
    last = first;
    local.clear();
    while (last < vertexFaces.size() && vertexFaces[last].first == v) local.push_back(vertexFaces[last++].second);
    parent.resize(local.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](std::uint32_t x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    spokes.clear();
    for (std::uint32_t l = 0; l < local.size(); ++l)
      for (VertexId u : faces[local[l]].corner)
        if (u != v) spokes.emplace_back(u, l);
    std::sort(spokes.begin(), spokes.end());
    std::size_t fans = local.size();
    for (std::size_t n = 1; n < spokes.size(); ++n)
      if (spokes[n].first == spokes[n - 1].first) {
        const std::uint32_t x = root(spokes[n].second), y = root(spokes[n - 1].second);
        if (x != y) {
          parent[x] = y;
          --fans;
        }
      }
    if (fans > 1) {
      ++nonConvexVertices_;
      featurePoints.push_back(points[v]);
    }
  }

  // Each vertex's longest edge.
  std::vector<double> longest(points.size(), 0.0);
  for (const Cell& cell : cells_)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const double l = norm(points[cell.corner[b]] - points[cell.corner[a]]);
        longest[cell.corner[a]] = std::max(longest[cell.corner[a]], l);
        longest[cell.corner[b]] = std::max(longest[cell.corner[b]], l);
      }

  constexpr float kFar = std::numeric_limits<float>::infinity();
  clearance_.assign(points.size(), kFar);
  convexReach_.assign(points.size(), kFar);
  if (!featureSegments.empty() || !featurePoints.empty()) {
    // The grid: the bounding box of the tetrahedra's corners in cubic cells,
    // about two per vertex (at most eight).
    Vec3d low{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
              std::numeric_limits<double>::infinity()};
    Vec3d high = -1.0 * low;
    std::size_t used = 0;
    for (VertexId v = 0; v < points.size(); ++v) {
      if (firstAround_[v] == firstAround_[v + 1]) continue;
      ++used;
      low = {std::min(low.x, points[v].x), std::min(low.y, points[v].y), std::min(low.z, points[v].z)};
      high = {std::max(high.x, points[v].x), std::max(high.y, points[v].y), std::max(high.z, points[v].z)};
    }
    const Vec3d extent = high - low;
    const double largest = std::max({extent.x, extent.y, extent.z});
    const double floorExtent = 1e-6 * largest;
    double width = std::cbrt(std::max(extent.x, floorExtent) * std::max(extent.y, floorExtent) *
                             std::max(extent.z, floorExtent) / (2.0 * static_cast<double>(used)));
    std::array<std::size_t, 3> n{};
    for (;; width *= 1.25) {
      n = {static_cast<std::size_t>(extent.x / width) + 1, static_cast<std::size_t>(extent.y / width) + 1,
           static_cast<std::size_t>(extent.z / width) + 1};
      if (n[0] * n[1] * n[2] <= 8 * used + 64) break;
    }
    const double origin[3] = {low.x, low.y, low.z};
    auto cellOf = [&](double x, int axis) {
      const double i = std::floor((x - origin[axis]) / width);
      return static_cast<std::size_t>(std::clamp(i, 0.0, static_cast<double>(n[axis] - 1)));
    };
    auto cellIndex = [&](Vec3d p) { return cellOf(p.x, 0) + n[0] * (cellOf(p.y, 1) + n[1] * cellOf(p.z, 2)); };
    constexpr double kNoFeature = 1e20;
    std::vector<double> field(n[0] * n[1] * n[2], kNoFeature);
    auto mark = [&](Vec3d p, Vec3d q) {  // every cell the box of p and q overlaps
      const std::size_t i0 = cellOf(std::min(p.x, q.x), 0), i1 = cellOf(std::max(p.x, q.x), 0);
      const std::size_t j0 = cellOf(std::min(p.y, q.y), 1), j1 = cellOf(std::max(p.y, q.y), 1);
      const std::size_t k0 = cellOf(std::min(p.z, q.z), 2), k1 = cellOf(std::max(p.z, q.z), 2);
      for (std::size_t k = k0; k <= k1; ++k)
        for (std::size_t j = j0; j <= j1; ++j)
          for (std::size_t i = i0; i <= i1; ++i) field[i + n[0] * (j + n[1] * k)] = 0.0;
    };
    for (const auto& segment : featureSegments) {
      // In pieces no longer than a cell, so that their boxes hug the edge.
      const int pieces = std::max(1, static_cast<int>(std::ceil(norm(segment[1] - segment[0]) / width)));
      for (int m = 0; m < pieces; ++m)
        mark(segment[0] + (static_cast<double>(m) / pieces) * (segment[1] - segment[0]),
             segment[0] + (static_cast<double>(m + 1) / pieces) * (segment[1] - segment[0]));
    }
    for (const Vec3d& p : featurePoints) mark(p, p);
    // Separable: along x, then y, then z.
    std::vector<double> line, result;
    std::vector<std::size_t> parabola;
    std::vector<double> boundary;
    const std::size_t stride[3] = {1, n[0], n[0] * n[1]};
    for (int axis = 0; axis < 3; ++axis) {
      const int u = (axis + 1) % 3, w = (axis + 2) % 3;
      line.resize(n[axis]);
      result.resize(n[axis]);
      for (std::size_t b = 0; b < n[w]; ++b)
        for (std::size_t a = 0; a < n[u]; ++a) {
          const std::size_t base = a * stride[u] + b * stride[w];
          for (std::size_t q = 0; q < n[axis]; ++q) line[q] = field[base + q * stride[axis]];
          distanceTransformLine(line.data(), n[axis], result.data(), parabola, boundary);
          for (std::size_t q = 0; q < n[axis]; ++q) field[base + q * stride[axis]] = result[q];
        }
    }
    for (VertexId v = 0; v < points.size(); ++v) {
      if (firstAround_[v] == firstAround_[v + 1]) continue;
      const double cells = std::sqrt(field[cellIndex(points[v])]);
      // A little less, for the rounding of the float chain vectors it is
      // compared with.
      clearance_[v] = static_cast<float>(std::max(0.0, cells - std::sqrt(3.0)) * width * (1.0 - 1e-5));
    }
  }
  for (VertexId v = 0; v < points.size(); ++v)
    convexReach_[v] = longest[v] < clearance_[v] ? clearance_[v] : 0.f;
}

}  // namespace stvd
