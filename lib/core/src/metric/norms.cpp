#include "stvd/metric/norms.hpp"

#include <cmath>
#include <sstream>

namespace stvd {

std::string spdViolation(const SymTensor3& g) {
  const double a[6] = {g.xx, g.xy, g.xz, g.yy, g.yz, g.zz};
  for (double c : a)
    if (!std::isfinite(c)) return "tensor has a non-finite component";
  // Cholesky factorisation G = L L^T; a non-positive pivot means G is not
  // positive definite.
  const double l00 = g.xx;
  if (!(l00 > 0.0)) return "tensor is not positive definite (xx <= 0)";
  const double s00 = std::sqrt(l00);
  const double l10 = g.xy / s00, l20 = g.xz / s00;
  const double p1 = g.yy - l10 * l10;
  if (!(p1 > 0.0)) return "tensor is not positive definite (second pivot <= 0)";
  const double s11 = std::sqrt(p1);
  const double l21 = (g.yz - l20 * l10) / s11;
  const double p2 = g.zz - l20 * l20 - l21 * l21;
  if (!(p2 > 0.0)) return "tensor is not positive definite (third pivot <= 0)";
  return {};
}

std::string RiemannianNorm::invalidReason(const VertexParams& g) { return spdViolation(g); }

std::string RandersNorm::invalidReason(const VertexParams& p) {
  std::string why = spdViolation(p.m);
  if (!why.empty()) return why;
  const Vec3f w = p.omega;
  if (!(std::isfinite(w.x) && std::isfinite(w.y) && std::isfinite(w.z)))
    return "drift omega has a non-finite component";
  // omega^T M^-1 omega < 1, through the same Cholesky factor: solve L y = omega.
  const double s00 = std::sqrt(double(p.m.xx));
  const double l10 = p.m.xy / s00, l20 = p.m.xz / s00;
  const double s11 = std::sqrt(p.m.yy - l10 * l10);
  const double l21 = (p.m.yz - l20 * l10) / s11;
  const double s22 = std::sqrt(p.m.zz - l20 * l20 - l21 * l21);
  const double y0 = w.x / s00;
  const double y1 = (w.y - l10 * y0) / s11;
  const double y2 = (w.z - l20 * y0 - l21 * y1) / s22;
  const double q = y0 * y0 + y1 * y1 + y2 * y2;
  if (!(q < 1.0)) {
    std::ostringstream s;
    s << "drift too strong for a Randers norm (omega^T M^-1 omega = " << q << ", must be < 1)";
    return s.str();
  }
  return {};
}

}  // namespace stvd
