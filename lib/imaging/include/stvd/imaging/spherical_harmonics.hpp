// Real, even-order spherical harmonics as the diffusion-MRI programs define
// them: the bases in which fibre orientation distributions (FODs) are
// stored. docs/fod.md states each basis and checks it against DIPY and
// MRtrix3.
//
// Every basis here numbers its functions the same way: degree l = 0, 2, 4,
// ..., lmax, and within a degree m = -l, ..., l, so that function (l, m) is
// number l(l+1)/2 + m; lmax 2, 4, 6, 8, 10, 12 have 6, 15, 28, 45, 66, 91
// functions. They differ in which of cos(m phi) and sin(m phi) goes with
// m > 0, in a factor sqrt(2) and in a sign (-1)^m:
//
//   N_l^m P_l^m(cos theta) with the Condon-Shortley phase (as scipy's sph_harm)
//   written K_l^m below; theta the polar angle from the frame's z axis, phi
//   the azimuth from its x axis towards its y axis.
//
//   basis                m > 0                  m = 0     m < 0
//   Tournier07           sqrt2 K_l^m cos(m phi)  K_l^0   sqrt2 K_l^|m| sin(|m| phi)
//   Tournier07Legacy     K_l^m cos(m phi)        K_l^0   K_l^|m| sin(|m| phi)
//   Descoteaux07         sqrt2 K_l^m sin(m phi)  K_l^0   (-1)^m sqrt2 K_l^|m| cos(|m| phi)
//   Descoteaux07Legacy   sqrt2 K_l^m sin(m phi)  K_l^0   sqrt2 K_l^|m| cos(|m| phi)
//
// Tournier07 is MRtrix3's basis (orthonormal; DIPY's "tournier07" with
// legacy=False); Tournier07Legacy is MRtrix 0.2's (not normalised; DIPY's
// "tournier07" with legacy=True, DIPY 1.6's default); Descoteaux07 is the
// basis of Descoteaux et al. 2007 (DIPY's "descoteaux07" with legacy=False);
// Descoteaux07Legacy is DIPY's long-standing implementation of it, which
// takes |m| for m < 0 (DIPY's "descoteaux07" with legacy=True, DIPY 1.6's
// default).
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace stvd::imaging {

enum class ShBasis { Tournier07, Tournier07Legacy, Descoteaux07, Descoteaux07Legacy };

/// "tournier07" (alias "mrtrix3"), "tournier07_legacy", "descoteaux07",
/// "descoteaux07_legacy" (hyphens accepted for underscores); nullopt otherwise.
std::optional<ShBasis> parseShBasis(const std::string& name);
/// The canonical name, e.g. "descoteaux07_legacy".
std::string shBasisName(ShBasis basis);
/// The accepted names, for messages.
std::string shBasisNames();

/// (lmax + 1)(lmax + 2) / 2: the functions of even degree up to lmax.
int shCoefficientCount(int lmax);
/// The even lmax with that many functions (0 to kMaxShDegree), or nullopt.
std::optional<int> shDegreeOfCount(std::size_t count);
/// The highest degree read: lmax 12, 91 functions.
inline constexpr int kMaxShDegree = 12;

/// The functions of degree up to lmax (even, 0..kMaxShDegree) of `basis` at
/// the unit vector (x, y, z) of the basis's own frame, in double precision:
/// `out` gets shCoefficientCount(lmax) values. (x, y, z) need not be exactly
/// of length 1: it is normalised first. Throws std::invalid_argument for a
/// zero or non-finite vector or an lmax out of range.
void evaluateShBasis(ShBasis basis, int lmax, double x, double y, double z, double* out);
std::vector<double> evaluateShBasis(ShBasis basis, int lmax, double x, double y, double z);

}  // namespace stvd::imaging
