// What the front ends (the tool and the Python package) share in the core:
// the propagation choice with its defaults, checks and messages, and the
// regions of a label image.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "stvd/voxel_grid/label_regions.hpp"
#include "stvd/front_end/propagation_choice.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"
#include "stvd/surface/surface_propagation.hpp"

namespace stvd {
namespace {

std::string optionMessage(void (*set)(PropagationChoice&, const std::string&), const std::string& value) {
  PropagationChoice choice;
  try {
    set(choice, value);
  } catch (const OptionError& e) {
    return e.what();
  }
  return "";
}

TEST(PropagationChoice, DefaultsAreTheLibrarysPerKindOfDomain) {
  const PropagationChoice choice;
  EXPECT_EQ(choice.method, Method::ShortTermVectorDijkstra);
  EXPECT_FALSE(choice.lanthier);
  EXPECT_FALSE(choice.k.has_value());  // the domain's default, decided by the propagation
  EXPECT_EQ(choice.chainMeasure, kDefaultChainMeasure);
  EXPECT_EQ(choice.stencil, "26");
  const PropagationOptions options = propagationOptions(choice);
  EXPECT_FALSE(options.k.has_value());
  EXPECT_EQ(options.chainMeasure, kDefaultChainMeasure);
  EXPECT_EQ(memoryDepthOf<VoxelGridDomain>(choice), kDefaultMemoryDepth);
  EXPECT_EQ(memoryDepthOf<SurfaceDomain>(choice), kDefaultSurfaceMemoryDepth);
  EXPECT_EQ(methodName(choice), "stvd");
  EXPECT_EQ(methodText(choice, memoryDepthOf<VoxelGridDomain>(choice)), "STVD with k = 6 (segment measure)");

  PropagationChoice stated;
  setMemoryDepth(stated, 3);
  EXPECT_EQ(memoryDepthOf<VoxelGridDomain>(stated), 3);
  EXPECT_EQ(memoryDepthOf<SurfaceDomain>(stated), 3);
}

TEST(PropagationChoice, DijkstraRunsWithMemoryDepthOne) {
  PropagationChoice choice;
  setMethod(choice, "dijkstra");
  EXPECT_EQ(propagationOptions(choice).method, Method::Dijkstra);
  EXPECT_EQ(propagationOptions(choice).k, 1);
  EXPECT_EQ(memoryDepthOf<SurfaceDomain>(choice), 1);
  EXPECT_EQ(methodText(choice, 1), "Dijkstra");
}

TEST(PropagationChoice, ValuesOutsideTheAcceptedOnesGiveTheToolsMessages) {
  EXPECT_EQ(optionMessage(setMethod, "fast"), "--method: 'fast' is not one of stvd, dijkstra, lanthier");
  EXPECT_EQ(optionMessage(setChainMeasure, "mean"), "--chain-measure: 'mean' is not one of segment, projection, largest");
  EXPECT_EQ(optionMessage(setStencil, "27"), "--stencil: '27' is not one of 6, 18, 26, 98, 290");
  PropagationChoice choice;
  EXPECT_THROW(setMemoryDepth(choice, kMaxMemoryDepth + 1), OptionError);
  EXPECT_THROW(setMemoryDepth(choice, 0), OptionError);
  EXPECT_THROW(setSteinerPoints(choice, 0), OptionError);
  setMemoryDepth(choice, 3);
  setChainMeasure(choice, "largest");
  EXPECT_EQ(methodText(choice, memoryDepthOf<VoxelGridDomain>(choice)), "STVD with k = 3 (largest-norm chain measure)");
}

TEST(PropagationChoice, CombinationsThatMakeNoSenseAreRefused) {
  PropagationChoice dijkstraWithK;
  setMethod(dijkstraWithK, "dijkstra");
  setMemoryDepth(dijkstraWithK, 3);
  EXPECT_THROW(checkPropagationChoice(dijkstraWithK, true), OptionError);
  // Meshes accept and ignore k with Dijkstra, as they always have.
  EXPECT_NO_THROW(checkMeshPropagationChoice(dijkstraWithK, "face edge", 4));

  PropagationChoice lanthier;
  setMethod(lanthier, "lanthier");
  try {
    checkPropagationChoice(lanthier, true);
    ADD_FAILURE() << "lanthier without --steiner was accepted";
  } catch (const OptionError& e) {
    EXPECT_EQ(std::string(e.what()), "--method lanthier needs --steiner M, the Steiner points per cube edge (1..16; try 2)");
  }
  setSteinerPoints(lanthier, 2);
  EXPECT_NO_THROW(checkPropagationChoice(lanthier, true));
  EXPECT_THROW(checkPropagationChoice(lanthier, /*lanthierAllowed=*/false), OptionError);  // paths need predecessors
  setStencil(lanthier, "6");
  EXPECT_THROW(checkPropagationChoice(lanthier, true), OptionError);
}

TEST(LabelRegions, OneRegionPerLabelInIncreasingOrderWithItsVoxelsInTheDomain) {
  const std::vector<std::int64_t> labels{0, 7, 2, 7, 0, 2, 9};
  const std::vector<std::uint8_t> inDomain{1, 1, 0, 1, 1, 1, 0};
  const std::vector<LabelRegion> regions = labelRegions(labels, inDomain);
  ASSERT_EQ(regions.size(), 3u);
  EXPECT_EQ(regions[0].label, 2);
  EXPECT_EQ(regions[0].voxels, (std::vector<VertexId>{5}));
  EXPECT_EQ(regions[1].label, 7);
  EXPECT_EQ(regions[1].voxels, (std::vector<VertexId>{1, 3}));
  EXPECT_EQ(regions[2].label, 9);
  EXPECT_TRUE(regions[2].voxels.empty());  // kept: the caller says what it means

  std::size_t leftOut = 0;
  const std::vector<LabelRegion> connectable = regionsInDomain(regions, "labels", "tensors", leftOut);
  EXPECT_EQ(connectable.size(), 2u);
  EXPECT_EQ(leftOut, 1u);
  leftOut = 0;
  EXPECT_THROW(regionsInDomain({regions[0], regions[2]}, "labels", "tensors", leftOut), NothingToCompute);
}

TEST(LabelRegions, TheNearestReachedVertexIsTheFirstOfTheSmallestFiniteDistances) {
  const std::vector<double> distance{kUnreachable, 3.0, 1.0, 1.0, 0.5};
  EXPECT_EQ(nearestReached(distance, {0, 1, 2, 3}), 2u);
  EXPECT_EQ(nearestReached(distance, {3, 2}), 3u);
  EXPECT_EQ(nearestReached(distance, {0}), kNoVertex);
  EXPECT_EQ(nearestReached(distance, {}), kNoVertex);
}

}  // namespace
}  // namespace stvd
