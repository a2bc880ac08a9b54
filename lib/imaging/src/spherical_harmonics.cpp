#include "stvd/imaging/spherical_harmonics.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>

namespace stvd::imaging {

std::optional<ShBasis> parseShBasis(const std::string& name) {
  std::string n = name;
  std::replace(n.begin(), n.end(), '-', '_');
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (n == "tournier07" || n == "mrtrix3") return ShBasis::Tournier07;
  if (n == "tournier07_legacy") return ShBasis::Tournier07Legacy;
  if (n == "descoteaux07") return ShBasis::Descoteaux07;
  if (n == "descoteaux07_legacy") return ShBasis::Descoteaux07Legacy;
  return std::nullopt;
}

std::string shBasisName(ShBasis basis) {
  switch (basis) {
    case ShBasis::Tournier07: return "tournier07";
    case ShBasis::Tournier07Legacy: return "tournier07_legacy";
    case ShBasis::Descoteaux07: return "descoteaux07";
    case ShBasis::Descoteaux07Legacy: return "descoteaux07_legacy";
  }
  return "?";
}

std::string shBasisNames() {
  return "tournier07 (alias mrtrix3), tournier07_legacy, descoteaux07, descoteaux07_legacy";
}

int shCoefficientCount(int lmax) { return (lmax + 1) * (lmax + 2) / 2; }

std::optional<int> shDegreeOfCount(std::size_t count) {
  for (int l = 0; l <= kMaxShDegree; l += 2)
    if (static_cast<std::size_t>(shCoefficientCount(l)) == count) return l;
  return std::nullopt;
}

void evaluateShBasis(ShBasis basis, int lmax, double x, double y, double z, double* out) {
  if (lmax < 0 || lmax > kMaxShDegree || lmax % 2 != 0)
    throw std::invalid_argument("spherical harmonics: lmax " + std::to_string(lmax) +
                                " is not an even degree from 0 to " + std::to_string(kMaxShDegree));
  const double r = std::sqrt(x * x + y * y + z * z);
  if (!(r > 0.0) || !std::isfinite(r))
    throw std::invalid_argument("spherical harmonics: the direction is zero or not finite");
  const double ct = std::clamp(z / r, -1.0, 1.0);
  const double st = std::sqrt(std::max(0.0, 1.0 - ct * ct));
  const double phi = std::atan2(y, x);

  // Normalised associated Legendre functions with the Condon-Shortley phase,
  // p[l][m] = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!) P_l^m(cos theta), by the
  // stable recurrences in m (diagonal) and l.
  constexpr int L = kMaxShDegree;
  std::array<std::array<double, L + 1>, L + 1> p{};
  p[0][0] = 1.0 / std::sqrt(4.0 * M_PI);
  for (int m = 1; m <= lmax; ++m) p[m][m] = -std::sqrt((2.0 * m + 1.0) / (2.0 * m)) * st * p[m - 1][m - 1];
  for (int m = 0; m < lmax; ++m) p[m + 1][m] = std::sqrt(2.0 * m + 3.0) * ct * p[m][m];
  for (int m = 0; m <= lmax; ++m)
    for (int l = m + 2; l <= lmax; ++l) {
      const double a = std::sqrt((4.0 * l * l - 1.0) / (double(l) * l - double(m) * m));
      const double b = std::sqrt((double(l - 1) * (l - 1) - double(m) * m) / (4.0 * (l - 1) * (l - 1) - 1.0));
      p[l][m] = a * (ct * p[l - 1][m] - b * p[l - 2][m]);
    }

  const bool legacyScale = basis == ShBasis::Tournier07Legacy;
  const double s2 = legacyScale ? 1.0 : std::sqrt(2.0);
  for (int l = 0; l <= lmax; l += 2) {
    const int centre = l * (l + 1) / 2;
    out[centre] = p[l][0];
    for (int m = 1; m <= l; ++m) {
      const double c = std::cos(m * phi), s = std::sin(m * phi);
      const double k = s2 * p[l][m];
      switch (basis) {
        case ShBasis::Tournier07:
        case ShBasis::Tournier07Legacy:
          out[centre + m] = k * c;
          out[centre - m] = k * s;
          break;
        case ShBasis::Descoteaux07:
          out[centre + m] = k * s;
          out[centre - m] = (m % 2 ? -1.0 : 1.0) * k * c;
          break;
        case ShBasis::Descoteaux07Legacy:
          out[centre + m] = k * s;
          out[centre - m] = k * c;
          break;
      }
    }
  }
}

std::vector<double> evaluateShBasis(ShBasis basis, int lmax, double x, double y, double z) {
  std::vector<double> out(static_cast<std::size_t>(shCoefficientCount(lmax)));
  evaluateShBasis(basis, lmax, x, y, z, out.data());
  return out;
}

}  // namespace stvd::imaging
