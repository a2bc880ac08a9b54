// The generalised fractional anisotropy (GFA; Tuch, "Q-ball imaging", 2004)
// of an FOD image, from its spherical-harmonic coefficients: what the QC
// pages of FOD runs draw under the paths, as tensor pages draw FA
// (docs/fod.md, docs/report.md).
#pragma once

#include <vector>

#include "stvd/imaging/fod_field.hpp"

namespace stvd::imaging {

/// GFA = std(psi) / rms(psi) of the FOD psi over the sphere, per voxel
/// (the field's voxel order), from the coefficients alone:
///
///     GFA = sqrt(1 - c_00^2 / sum_j n_j c_j^2)
///
/// with n_j the squared norm of basis function j over the sphere: 1 for the
/// orthonormal bases (tournier07, descoteaux07 and descoteaux07_legacy:
/// their sqrt(2) factors make the real functions orthonormal, signs aside),
/// 1/2 for the m != 0 functions of tournier07_legacy (no sqrt(2)). The
/// mean of psi is c_00 Y_00 and its mean square sum_j n_j c_j^2 / (4 pi), so
/// this is DIPY's `gfa` of psi sampled on a sphere in the limit of dense
/// sampling. 0 where every coefficient is 0 (outside the fit's mask), and
/// in [0, 1] everywhere.
std::vector<float> fodGeneralisedFa(const FodField& field);

}  // namespace stvd::imaging
