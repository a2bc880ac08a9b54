// The voxel grid as a graph: the runs of vertex numbers that the
// propagation prefetches must hold every neighbour the grid reports.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "scenes.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {
namespace {

struct Run {
  VertexId first, last;
};

void expectRunsHoldEveryNeighbour(const VoxelGridDomain& domain) {
  for (VertexId v = 0; v < domain.vertexCount(); ++v) {
    std::vector<Run> runs;
    domain.forEachNeighborRun(v, [&](VertexId first, VertexId last) {
      EXPECT_LE(first, last);
      EXPECT_LT(last, domain.vertexCount());
      runs.push_back({first, last});
    });
    domain.forEachNeighbor(v, [&](VertexId w, Vec3f) {
      bool held = false;
      for (const Run& r : runs) held = held || (r.first <= w && w <= r.last);
      EXPECT_TRUE(held) << "neighbour " << w << " of vertex " << v << " is in no run";
    });
    // A run is one row of the stencil's bounding block: at most 2r + 1 voxels.
    for (const Run& r : runs)
      EXPECT_LE(r.last - r.first + 1, static_cast<VertexId>(2 * domain.stencil().radius() + 1));
  }
}

TEST(VoxelGridNeighbourRuns, HoldEveryNeighbourOfThe26Neighbourhood) {
  expectRunsHoldEveryNeighbour(VoxelGridDomain(test::obliqueGrid({5, 4, 3}), Stencil::full26()));
}

TEST(VoxelGridNeighbourRuns, HoldEveryNeighbourOfTheRadius3StencilOnAGridThinnerThanIt) {
  // Corners, edges and faces of the image cut the runs on every side.
  expectRunsHoldEveryNeighbour(VoxelGridDomain(test::obliqueGrid({9, 2, 4}), Stencil::primitive(3)));
}

TEST(VoxelGridNeighbourRuns, HoldEveryNeighbourOfASingleRow) {
  expectRunsHoldEveryNeighbour(VoxelGridDomain(test::obliqueGrid({7, 1, 1}), Stencil::faces6()));
}

}  // namespace
}  // namespace stvd

namespace stvd {
namespace {

// An index past an edge of the image is refused, not read as another voxel:
// in linear order (nx, 0, 0) would be (0, 1, 0).
TEST(VoxelGridDomainIndex, AnIndexOutsideTheImageIsRefused) {
  const VoxelGridDomain domain(test::obliqueGrid({5, 4, 3}), Stencil::full26());
  EXPECT_EQ(domain.vertexAt(4, 3, 2), domain.vertexCount() - 1);
  EXPECT_EQ(domain.vertexAt(0, 1, 0), 5u);
  EXPECT_THROW(domain.vertexAt(5, 0, 0), std::out_of_range);
  EXPECT_THROW(domain.vertexAt(0, 4, 0), std::out_of_range);
  EXPECT_THROW(domain.vertexAt(0, 0, 3), std::out_of_range);
  EXPECT_THROW(domain.vertexAt(-1, 0, 0), std::out_of_range);
  try {
    domain.vertexAt(5, 0, 0);
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("(5, 0, 0) is outside the image of 5 x 4 x 3 voxels"), std::string::npos)
        << e.what();
  }
  // The unchecked accessor stays for loops that stay inside by construction.
  EXPECT_EQ(domain.vertexAtUnchecked(5, 0, 0), domain.vertexAtUnchecked(0, 1, 0));
}

}  // namespace
}  // namespace stvd
