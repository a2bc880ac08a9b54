// STVD with memory depth k = 1 only ever uses the edge v -> w, which is
// Dijkstra's update: the two must agree bit for bit (distances compared
// with memcmp, predecessors and counters identical), whatever the metric,
// mask, norm or domain.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

#include "scenes.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "stvd/cell_mesh/cell_mesh_propagation.hpp"

namespace stvd {
namespace {

template <class Domain, class Norm>
void expectDepthOneIsDijkstra(const Domain& domain, const MetricField<Norm>& metric,
                              const std::vector<VertexId>& sources) {
  const PropagationResult d = dijkstra(domain, metric, sources);
  const PropagationResult s = shortTermVectorDijkstra(domain, metric, sources, 1);
  ASSERT_EQ(d.distance.size(), s.distance.size());
  EXPECT_EQ(std::memcmp(d.distance.data(), s.distance.data(), d.distance.size() * sizeof(double)), 0);
  EXPECT_EQ(d.predecessor, s.predecessor);
  EXPECT_EQ(d.termination, s.termination);
  EXPECT_EQ(d.finalizedVertices, s.finalizedVertices);
  EXPECT_EQ(d.relaxedEdges, s.relaxedEdges);
  // Not vacuous: the metric varies, so distances are not a scaled grid metric,
  // and most vertices were reached.
  std::size_t reached = 0;
  for (double x : d.distance) reached += x < kUnreachable ? 1 : 0;
  EXPECT_GT(reached, d.distance.size() / 3);
}

std::vector<std::uint8_t> ballWithCavityMask(const GridGeometry& g) {
  // A ball with a spherical cavity, so that fronts must flow around an obstacle.
  std::vector<std::uint8_t> mask = test::ballMask(g, {15, 14, 13}, 14.0);
  const std::vector<std::uint8_t> cavity = test::ballMask(g, {18, 14, 13}, 5.0);
  for (std::size_t v = 0; v < mask.size(); ++v) mask[v] = mask[v] && !cavity[v];
  return mask;
}

TEST(MemoryDepthOne, EqualsDijkstraOnVaryingMetricWithMask) {
  const GridGeometry g = test::obliqueGrid({32, 30, 28});
  const VoxelGridDomain domain(g, Stencil::full26(), ballWithCavityMask(g));
  const RiemannianMetric metric(test::smoothVaryingTensors(domain), &domain.mask());
  expectDepthOneIsDijkstra(domain, metric, {domain.vertexAt(8, 14, 13), domain.vertexAt(25, 9, 10)});
}

TEST(MemoryDepthOne, EqualsDijkstraWithLargeStencil) {
  const VoxelGridDomain domain(test::obliqueGrid({20, 18, 16}), Stencil::primitive(3));
  const RiemannianMetric metric(test::smoothVaryingTensors(domain));
  expectDepthOneIsDijkstra(domain, metric, {domain.vertexAt(2, 9, 8)});
}

TEST(MemoryDepthOne, EqualsDijkstraForRandersNorm) {
  const GridGeometry g = test::obliqueGrid({32, 30, 28});
  const VoxelGridDomain domain(g, Stencil::full26(), ballWithCavityMask(g));
  const RandersMetric metric(test::smoothVaryingRanders(domain), &domain.mask());
  expectDepthOneIsDijkstra(domain, metric, {domain.vertexAt(8, 14, 13)});
}

TEST(MemoryDepthOne, EqualsDijkstraOnTetrahedralMesh) {
  const test::TetrahedralBox box = test::kuhnTetrahedralBox({14, 12, 10}, {1.0, 1.3, 1.6}, 0.2, 3);
  const CellMeshDomain mesh = CellMeshDomain::fromTetrahedra(box.points, box.tets);
  std::vector<SymTensor3> tensors(mesh.vertexCount());
  for (VertexId v = 0; v < mesh.vertexCount(); ++v) {
    const Vec3d p = mesh.physicalPoint(v);
    tensors[v] = {static_cast<float>(2.0 + std::sin(p.x)), 0.3f, 0.0f,
                  static_cast<float>(1.5 + std::cos(p.y)), 0.2f, 1.0f};
  }
  expectDepthOneIsDijkstra(mesh, RiemannianMetric(tensors), {box.id(0, 0, 0), box.id(14, 6, 10)});
}

}  // namespace
}  // namespace stvd
