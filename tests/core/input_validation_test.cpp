// Invalid inputs are refused with std::invalid_argument, and the message
// names what is wrong (the offending vertex, cell or value).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "method_cases.hpp"
#include "scenes.hpp"
#include "stvd/cell_mesh/cell_mesh_domain.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "stvd/cell_mesh/cell_mesh_propagation.hpp"

namespace stvd {
namespace {

/// Expects f to throw std::invalid_argument with `fragment` in its message.
void expectInvalid(const std::function<void()>& f, const std::string& fragment) {
  try {
    f();
    ADD_FAILURE() << "no exception; expected one mentioning '" << fragment << "'";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos)
        << "message '" << e.what() << "' does not mention '" << fragment << "'";
  }
}

const SymTensor3 kIdentity{1, 0, 0, 1, 0, 1};

class PropagationInputs : public ::testing::Test {
 protected:
  PropagationInputs() {
    std::vector<std::uint8_t> mask(geometry_.voxelCount(), 1);
    mask[outsideVoxel_] = 0;
    domain_ = std::make_unique<VoxelGridDomain>(geometry_, Stencil::full26(), mask);
    metric_ = RiemannianMetric::constant(domain_->vertexCount(), kIdentity);
  }
  PropagationOptions stvd(int k) { return test::withMethod(Method::ShortTermVectorDijkstra, k); }

  GridGeometry geometry_ = test::obliqueGrid({6, 6, 6});
  VertexId outsideVoxel_ = 40;
  std::unique_ptr<VoxelGridDomain> domain_;
  RiemannianMetric metric_;
};

TEST_F(PropagationInputs, ValidInputsAreAccepted) {
  EXPECT_NO_THROW(propagate(*domain_, metric_, {0}, stvd(1)));
  EXPECT_NO_THROW(propagate(*domain_, metric_, {0}, stvd(kMaxMemoryDepth)));
  EXPECT_NO_THROW(dijkstra(*domain_, metric_, {0, 1, 0}));  // repeated sources are fine
}

TEST_F(PropagationInputs, MetricOfWrongSizeIsRefused) {
  const RiemannianMetric small = RiemannianMetric::constant(domain_->vertexCount() - 1, kIdentity);
  expectInvalid([&] { dijkstra(*domain_, small, {0}); }, "215");
  expectInvalid([&] { propagate(*domain_, small, {0}, stvd(8)); }, "216");
}

TEST_F(PropagationInputs, MissingSourceIsRefused) {
  expectInvalid([&] { dijkstra(*domain_, metric_, {}); }, "no source");
  expectInvalid([&] { propagate(*domain_, metric_, {}, stvd(8)); }, "no source");
}

TEST_F(PropagationInputs, SourceOutsideMaskOrGridIsRefused) {
  expectInvalid([&] { dijkstra(*domain_, metric_, {0, outsideVoxel_}); }, "40");
  expectInvalid([&] { propagate(*domain_, metric_, {outsideVoxel_}, stvd(8)); }, "40");
  expectInvalid([&] { dijkstra(*domain_, metric_, {216}); }, "216");
  expectInvalid([&] { dijkstra(*domain_, metric_, {kNoVertex}); }, std::to_string(kNoVertex));
}

TEST_F(PropagationInputs, MemoryDepthOutside1To16IsRefused) {
  expectInvalid([&] { propagate(*domain_, metric_, {0}, stvd(0)); }, "k = 0");
  expectInvalid([&] { propagate(*domain_, metric_, {0}, stvd(17)); }, "k = 17");
  expectInvalid([&] { propagate(*domain_, metric_, {0}, stvd(-3)); }, "k = -3");
  expectInvalid([&] { shortTermVectorDijkstra(*domain_, metric_, {0}, 17); }, "k = 17");
}

TEST_F(PropagationInputs, TargetOutsideDomainAndNanMaxDistanceAreRefused) {
  PropagationOptions o;
  o.targets = {3, outsideVoxel_};
  expectInvalid([&] { propagate(*domain_, metric_, {0}, o); }, "40");
  o.targets = {};
  o.maxDistance = std::nan("");
  expectInvalid([&] { propagate(*domain_, metric_, {0}, o); }, "NaN");
}

TEST(MetricFieldInputs, NonPositiveDefiniteOrNonFiniteTensorsAreRefused) {
  std::vector<SymTensor3> tensors(10, kIdentity);
  EXPECT_NO_THROW(RiemannianMetric{tensors});

  tensors[3] = {1, 0, 0, 1, 0, -0.5f};  // negative eigenvalue
  expectInvalid([&] { RiemannianMetric{tensors}; }, "vertex 3");
  tensors[3] = {1, 2, 0, 1, 0, 1};  // indefinite although the diagonal is positive
  expectInvalid([&] { RiemannianMetric{tensors}; }, "vertex 3");
  tensors[3] = {1, 1, 0, 1, 0, 1};  // singular (positive semi-definite only)
  expectInvalid([&] { RiemannianMetric{tensors}; }, "vertex 3");
  tensors[3] = {0, 0, 0, 0, 0, 0};
  expectInvalid([&] { RiemannianMetric{tensors}; }, "vertex 3");
  tensors[3] = kIdentity;
  tensors[7] = {1, 0, std::nanf(""), 1, 0, 1};
  expectInvalid([&] { RiemannianMetric{tensors}; }, "vertex 7");
  tensors[7] = {std::numeric_limits<float>::infinity(), 0, 0, 1, 0, 1};
  expectInvalid([&] { RiemannianMetric{tensors}; }, "vertex 7");
}

TEST(MetricFieldInputs, OnlyVerticesInsideTheDomainAreValidated) {
  std::vector<SymTensor3> tensors(10, kIdentity);
  tensors[4] = {0, 0, 0, 0, 0, 0};  // background voxel of a masked image
  std::vector<std::uint8_t> inDomain(10, 1);
  inDomain[4] = 0;
  EXPECT_NO_THROW(RiemannianMetric(tensors, &inDomain));
  inDomain[4] = 1;
  expectInvalid([&] { RiemannianMetric(tensors, &inDomain); }, "vertex 4");
}

TEST(MetricFieldInputs, RandersDriftMustBeWeakerThanTheRiemannianPart) {
  // M = diag(4, 1, 1): omega^T M^-1 omega = omega_x^2 / 4 + omega_y^2 + omega_z^2.
  const SymTensor3 m{4, 0, 0, 1, 0, 1};
  std::vector<RandersNorm::VertexParams> params(5, {m, {1.9f, 0, 0}});  // 0.9025
  EXPECT_NO_THROW(RandersMetric{params});
  params[2].omega = {2.0f, 0, 0};  // exactly 1: F vanishes along -x
  expectInvalid([&] { RandersMetric{params}; }, "vertex 2");
  params[2].omega = {0, 1.2f, 0};
  expectInvalid([&] { RandersMetric{params}; }, "drift");
  params[2].omega = {0, 0, std::nanf("")};
  expectInvalid([&] { RandersMetric{params}; }, "vertex 2");
  params[2] = {{1, 0, 0, -1, 0, 1}, {0, 0, 0}};  // Riemannian part not SPD
  expectInvalid([&] { RandersMetric{params}; }, "vertex 2");
}

TEST(CellMeshInputs, IndicesOutOfRangeAndDegenerateCellsAreRefused) {
  const std::vector<Vec3d> points{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}};
  EXPECT_NO_THROW(CellMeshDomain::fromTetrahedra(points, {{0, 1, 2, 3}, {1, 2, 3, 4}}));
  expectInvalid([&] { CellMeshDomain::fromTetrahedra(points, {{0, 1, 2, 3}, {1, 2, 3, 5}}); },
                "tetrahedron 1");
  expectInvalid([&] { CellMeshDomain::fromTetrahedra(points, {{0, 1, 1, 3}}); }, "tetrahedron 0");

  const CellMeshDomain::PolyhedralCell pyramid{{0, 1, 4, 2}, {0, 1, 3}, {1, 4, 3}, {4, 2, 3}, {2, 0, 3}};
  EXPECT_NO_THROW(CellMeshDomain::fromPolyhedra(points, {pyramid}));
  CellMeshDomain::PolyhedralCell broken = pyramid;
  broken[2] = {1, 9, 3};
  expectInvalid([&] { CellMeshDomain::fromPolyhedra(points, {pyramid, broken}); }, "cell 1");
  broken = pyramid;
  broken[1] = {0, 1};
  expectInvalid([&] { CellMeshDomain::fromPolyhedra(points, {broken}); }, "cell 0");

  expectInvalid([&] { CellMeshDomain::fromEdges(points, {{0, 1}, {2, 5}}); }, "edge 1");
  std::vector<Vec3d> bad = points;
  bad[3].y = std::numeric_limits<double>::infinity();
  expectInvalid([&] { CellMeshDomain::fromEdges(bad, {{0, 1}}); }, "vertex 3");
}

TEST(CellMeshInputs, PropagationRefusesSourcesOutsideTheMesh) {
  const CellMeshDomain mesh =
      CellMeshDomain::fromTetrahedra({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 1, 2, 3}});
  const RiemannianMetric metric = RiemannianMetric::constant(4, kIdentity);
  EXPECT_NO_THROW(dijkstra(mesh, metric, {3}));
  expectInvalid([&] { dijkstra(mesh, metric, {4}); }, "4");
  const RiemannianMetric wrong = RiemannianMetric::constant(5, kIdentity);
  expectInvalid([&] { shortTermVectorDijkstra(mesh, wrong, {0}, 4); }, "5");
}

}  // namespace
}  // namespace stvd
