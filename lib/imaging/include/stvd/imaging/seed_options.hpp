// Seeds and path targets as the front ends take them (--seed-voxel,
// --seed-point, --lps, --seeds, --target-voxel, --target-point, --targets),
// declared once (stvd/front_end/option_declarations.hpp); seed_voxels.hpp turns
// them into voxels.
#pragma once

#include <array>
#include <vector>

#include "stvd/front_end/option_declarations.hpp"

namespace stvd::imaging {

const std::vector<OptionDeclaration>& seedOptionDeclarations();

/// "no seed: add --seed-voxel I,J,K, --seed-point X,Y,Z or --seeds LABELS",
/// or with keywords "no seed: add seeds=, seed_points= or seed_labels=".
std::string noSeedMessage(OptionNaming naming);
/// The same for path targets.
std::string noTargetMessage(OptionNaming naming);

/// The voxels ("I,J,K") and the points ("X,Y,Z") given to a repeatable
/// option, in order.
std::vector<std::array<int, 3>> voxelsOf(const OptionValues& values, const std::string& flag);
std::vector<std::array<double, 3>> pointsOf(const OptionValues& values, const std::string& flag);

}  // namespace stvd::imaging
