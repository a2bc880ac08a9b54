#include "kuhn_cube.hpp"

#include <array>
#include <utility>

#include "../core/kuhn_lattice.hpp"

namespace stvd::testing {

tetmesh::TetMesh kuhnCube(Vec3d origin, int firstIndex) {
  const int n = 4;
  tetmesh::TetMesh m;
  m.firstIndex = firstIndex;
  auto id = [&](int i, int j, int k) { return static_cast<VertexId>(i + (n + 1) * (j + (n + 1) * k)); };
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) m.points.push_back(origin + Vec3d{double(i), double(j), double(k)});
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        test::forEachKuhnTetrahedron(i, j, k, id, [&m](std::array<VertexId, 4> t) {
          if (tetmesh::signedVolume(m.points[t[0]], m.points[t[1]], m.points[t[2]], m.points[t[3]]) < 0)
            std::swap(t[2], t[3]);
          m.tets.push_back(t);
        });
  return m;
}

}  // namespace stvd::testing
