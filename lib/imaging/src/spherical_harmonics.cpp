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

  // The factors of the recurrences, computed once.
  constexpr int L = kMaxShDegree;
  struct Factors {
    double diagonal[L + 1], subdiagonal[L + 1], a[L + 1][L + 1], b[L + 1][L + 1];
  };
  static const Factors f = [] {
    Factors t{};
    for (int m = 1; m <= L; ++m) t.diagonal[m] = -std::sqrt((2.0 * m + 1.0) / (2.0 * m));
    for (int m = 0; m < L; ++m) t.subdiagonal[m] = std::sqrt(2.0 * m + 3.0);
    for (int m = 0; m <= L; ++m)
      for (int l = m + 2; l <= L; ++l) {
        t.a[l][m] = std::sqrt((4.0 * l * l - 1.0) / (double(l) * l - double(m) * m));
        t.b[l][m] = std::sqrt((double(l - 1) * (l - 1) - double(m) * m) / (4.0 * (l - 1) * (l - 1) - 1.0));
      }
    return t;
  }();

  // Normalised associated Legendre functions with the Condon-Shortley phase,
  // p[l][m] = sqrt((2l+1)/(4 pi) (l-m)!/(l+m)!) P_l^m(cos theta), by the
  // stable recurrences in m (diagonal) and l.
  double p[L + 1][L + 1];
  p[0][0] = 0.5 / std::sqrt(M_PI);
  for (int m = 1; m <= lmax; ++m) p[m][m] = f.diagonal[m] * st * p[m - 1][m - 1];
  for (int m = 0; m < lmax; ++m) p[m + 1][m] = f.subdiagonal[m] * ct * p[m][m];
  for (int m = 0; m <= lmax; ++m)
    for (int l = m + 2; l <= lmax; ++l) p[l][m] = f.a[l][m] * (ct * p[l - 1][m] - f.b[l][m] * p[l - 2][m]);

  // cos(m phi) and sin(m phi) by complex powers of (x + iy) / |(x, y)|: no
  // trigonometric call (at the poles phi is taken as 0; every m > 0 term
  // vanishes there).
  double cosm[L + 1], sinm[L + 1];
  const double rxy = std::sqrt(x * x + y * y);
  const double c1 = rxy > 0.0 ? x / rxy : 1.0, s1 = rxy > 0.0 ? y / rxy : 0.0;
  cosm[0] = 1.0;
  sinm[0] = 0.0;
  for (int m = 1; m <= lmax; ++m) {
    cosm[m] = cosm[m - 1] * c1 - sinm[m - 1] * s1;
    sinm[m] = sinm[m - 1] * c1 + cosm[m - 1] * s1;
  }

  const bool legacyScale = basis == ShBasis::Tournier07Legacy;
  const double s2 = legacyScale ? 1.0 : std::sqrt(2.0);
  for (int l = 0; l <= lmax; l += 2) {
    const int centre = l * (l + 1) / 2;
    out[centre] = p[l][0];
    for (int m = 1; m <= l; ++m) {
      const double c = cosm[m], s = sinm[m];
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
