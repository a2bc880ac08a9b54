// What the geodesic subcommands (distance, path, connectivity) share: the
// seed options and their resolution to voxels, and the propagation options
// (read into the library's PropagationChoice, stvd/propagation_choice.hpp,
// which holds the defaults and the checks).
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

/// When `option` is a seed option, reads it into `seeds` and returns true.
bool parseSeedOption(const std::string& option, ArgumentReader& args, SeedOptions& seeds);
/// When `option` is a propagation option (--method, --steiner, --k,
/// --chain-measure, --stencil, --domain-connectivity, --no-memory-check),
/// reads it into `choice` and returns true. Checks of the combination:
/// stvd::checkPropagationChoice.
bool parsePropagationOption(const std::string& option, ArgumentReader& args, PropagationChoice& choice);

// A voxel the user named and how (for messages), and how voxels and points
// are written in messages (stvd/itk/seed_voxels.hpp).
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
