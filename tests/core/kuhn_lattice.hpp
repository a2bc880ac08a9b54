// The Kuhn subdivision of a cube lattice into tetrahedra, shared by the
// tests and benchmarks that build tetrahedral meshes on a lattice.
#pragma once

#include <array>

#include "stvd/types.hpp"

namespace stvd::test {

/// The six tetrahedra of the lattice cube whose lowest corner is (i, j, k):
/// the six monotone lattice paths from that corner to the opposite one,
/// one per order of the three axes, all around the cube's (1,1,1)
/// diagonal. `id(i, j, k)` numbers a lattice vertex; `emit(t)` receives
/// each tetrahedron as the four vertices along its path, in that order.
template <class Id, class Emit>
void forEachKuhnTetrahedron(int i, int j, int k, Id&& id, Emit&& emit) {
  static constexpr int kOrders[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (const auto& order : kOrders) {
    int c[3] = {i, j, k};
    std::array<VertexId, 4> t;
    t[0] = id(c[0], c[1], c[2]);
    for (int step = 0; step < 3; ++step) {
      ++c[order[step]];
      t[step + 1] = id(c[0], c[1], c[2]);
    }
    emit(t);
  }
}

}  // namespace stvd::test
