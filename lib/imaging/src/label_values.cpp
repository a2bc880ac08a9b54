#include "stvd/imaging/label_values.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "stvd/errors.hpp"

namespace stvd::imaging {

namespace {

/// "(i, j, k)" of voxel number `v` of `g`, for messages.
std::string voxelText(const GridGeometry& g, std::size_t v) {
  return "(" + std::to_string(v % g.size[0]) + ", " + std::to_string((v / g.size[0]) % g.size[1]) + ", " +
         std::to_string(v / (static_cast<std::size_t>(g.size[0]) * g.size[1])) + ")";
}

}  // namespace

std::int64_t labelOfUnsigned64(std::uint64_t value, const std::string& name, const GridGeometry& g, std::size_t v) {
  if (value > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
    throw ImageIoError(name, "label " + std::to_string(value) + " at voxel " + voxelText(g, v) + " is beyond 2^63 - 1");
  return static_cast<std::int64_t>(value);
}

std::int64_t labelOfReal(double x, const std::string& name, const GridGeometry& g, std::size_t v) {
  constexpr double kLargestExact = 9007199254740992.0;  // 2^53
  if (std::isnan(x)) return 0;
  if (x != std::floor(x) || std::abs(x) > kLargestExact) {
    std::ostringstream s;
    s.precision(9);
    s << "voxel " << voxelText(g, v) << " holds " << x
      << (x != std::floor(x) ? ", which is not an integer" : ", beyond the 2^53 a floating-point label can hold exactly")
      << " (a label image holds integer labels)";
    throw ImageIoError(name, s.str());
  }
  return static_cast<std::int64_t>(x);
}

}  // namespace stvd::imaging
