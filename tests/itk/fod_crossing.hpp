// The synthetic crossing of the FOD tool tests, written as an FOD image:
// two bundles, 5 voxels wide, cross in the middle of a 25 x 25 x 3 grid of
// 1 mm voxels (index axes = LPS axes). Bundle 0 runs along i through
// j = 12; bundle 1 through the centre (12, 12) at `angleDegrees` from
// bundle 0 (90: along j through i = 12). Each voxel's FOD (lmax 8,
// tournier07 in DIPY's voxel frame, the default for DIPY's basis names in
// NIfTI) has one lobe per bundle it lies in, none outside (the floor's
// cost there).
#pragma once

#include <string>

#include "stvd/types.hpp"

namespace stvd::testing {

inline constexpr int kCrossingSize = 25, kCrossingCentre = 12, kCrossingHalfWidth = 2;

/// Bundle b's unit axis in index (= LPS) coordinates.
Vec3d crossingAxis(int bundle, double angleDegrees);

/// Distance (mm, in the plane of the bundles) of index point (i, j) from
/// bundle b's axis; the bundle holds the voxels within kCrossingHalfWidth.
double distanceFromCrossingAxis(int bundle, double angleDegrees, double i, double j);

/// Writes the crossing as a float32 NIfTI file (X Y Z 45).
void writeFodCrossing(const std::string& path, double angleDegrees = 90.0);

}  // namespace stvd::testing
