// The voxel grid as a graph: the runs of vertex numbers that the
// propagation prefetches must hold every neighbour the grid reports.
#include <gtest/gtest.h>

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
