// The closed surface of the L-shaped prism that the tet-mesh accuracy tests
// and benchmarks give TetGen to mesh.
#pragma once

#include "stvd/tetgen/tetrahedralize.hpp"

namespace stvd::test {

/// The L-shaped prism [0, 16] x [0, 16] x [0, 4] without the quadrant
/// x > 8, y > 8: two hexagons (bottom facing down, top facing up) and six
/// side quadrilaterals. Its geodesics bend around the notch x = y = 8
/// (lShapedPrismDistance in scenes.hpp, with half = 8).
inline tetgen::SurfaceMesh lShapedPrismSurface() {
  const double outline[6][2] = {{0, 0}, {16, 0}, {16, 8}, {8, 8}, {8, 16}, {0, 16}};
  tetgen::SurfaceMesh s;
  for (const double z : {0.0, 4.0})
    for (const auto& xy : outline) s.points.push_back({xy[0], xy[1], z});
  s.polygons.push_back({5, 4, 3, 2, 1, 0});
  s.polygons.push_back({6, 7, 8, 9, 10, 11});
  for (VertexId i = 0; i < 6; ++i) s.polygons.push_back({i, (i + 1) % 6, 6 + (i + 1) % 6, 6 + i});
  return s;
}

}  // namespace stvd::test
