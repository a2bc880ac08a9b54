// What the geodesic subcommands (distance, path, connectivity) share: the
// seed options and their resolution to voxels (their declarations:
// stvd/imaging/seed_options.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "stvd/imaging/seed_voxels.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/front_end/propagation_choice.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd::tool {

/// --seed-voxel, --seed-point, --lps, --seeds.
struct SeedOptions {
  std::vector<std::array<int, 3>> seedVoxels;
  std::vector<std::array<double, 3>> seedPoints;
  bool seedPointsInLps = false;
  std::string seedLabels;
};

/// The seed options given on a command line.
SeedOptions seedOptionsOf(const OptionValues& values);

// A voxel the user named and how (for messages), and how voxels and points
// are written in messages (stvd/imaging/seed_voxels.hpp).
using Seed = imaging::SeedVoxel;
using imaging::lpsToRas;
using imaging::pointText;
using imaging::voxelText;

/// The voxels of the seed options (imaging::seedVoxelsAt, then the label
/// image's voxels, imaging::labelSeedVoxels): voxels and points must lie in
/// the image and the domain (NothingToCompute naming `role`, "seed" or
/// "target", otherwise); label voxels outside the domain are left out and
/// counted.
std::vector<Seed> resolveSeeds(const std::string& inputPath, const SeedOptions& o, const TensorInput& input,
                               const imaging::MetricOptions& metric, const std::vector<std::uint8_t>& inDomain,
                               std::size_t& labelSeedsLeftOut, const std::string& role = "seed");

}  // namespace stvd::tool
