#include "stvd/voxel_grid/stencil.hpp"

#include <algorithm>
#include <cstdlib>
#include <numeric>
#include <set>
#include <stdexcept>

namespace stvd {

Stencil::Stencil(std::vector<Offset> offsets) : offsets_(std::move(offsets)) {
  for (const Offset& o : offsets_)
    for (int c : o) radius_ = std::max(radius_, std::abs(c));
}

Stencil Stencil::fromOffsets(std::vector<Offset> offsets) {
  if (offsets.empty()) throw std::invalid_argument("stencil: no offsets");
  const std::set<Offset> unique(offsets.begin(), offsets.end());
  if (unique.size() != offsets.size()) throw std::invalid_argument("stencil: repeated offset");
  for (const Offset& o : offsets) {
    if (o == Offset{0, 0, 0}) throw std::invalid_argument("stencil: offset (0,0,0)");
    if (!unique.count({-o[0], -o[1], -o[2]}))
      throw std::invalid_argument("stencil: offset (" + std::to_string(o[0]) + "," +
                                  std::to_string(o[1]) + "," + std::to_string(o[2]) +
                                  ") has no opposite");
  }
  return Stencil(std::move(offsets));
}

namespace {
// All offsets in [-r, r]^3 whose squared length is at most maxSquared and
// whose components have gcd 1 (when primitiveOnly).
std::vector<Stencil::Offset> block(int r, int maxSquared, bool primitiveOnly) {
  std::vector<Stencil::Offset> out;
  for (int k = -r; k <= r; ++k)
    for (int j = -r; j <= r; ++j)
      for (int i = -r; i <= r; ++i) {
        if (i == 0 && j == 0 && k == 0) continue;
        if (i * i + j * j + k * k > maxSquared) continue;
        if (primitiveOnly && std::gcd(std::gcd(std::abs(i), std::abs(j)), std::abs(k)) != 1)
          continue;
        out.push_back({i, j, k});
      }
  return out;
}
}  // namespace

Stencil Stencil::faces6() { return fromOffsets(block(1, 1, false)); }
Stencil Stencil::faces18() { return fromOffsets(block(1, 2, false)); }
Stencil Stencil::full26() { return fromOffsets(block(1, 3, false)); }

Stencil Stencil::primitive(int radius) {
  if (radius < 1 || radius > 5)
    throw std::invalid_argument("stencil: primitive radius must be 1..5, got " +
                                std::to_string(radius));
  return fromOffsets(block(radius, 3 * radius * radius, true));
}

Stencil Stencil::byName(const std::string& name) {
  if (name == "6") return faces6();
  if (name == "18") return faces18();
  if (name == "26") return full26();
  if (name == "98") return primitive(2);
  if (name == "290") return primitive(3);
  throw std::invalid_argument("unknown stencil '" + name +
                              "': use 6, 18, 26, 98 (5x5x5 primitive) or 290 (7x7x7 primitive)");
}

}  // namespace stvd
