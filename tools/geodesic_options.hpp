// What the geodesic subcommands (distance, path, connectivity) share: the
// seed options and their resolution to voxels, and the choice of the
// propagation method with the tool's defaults.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "stvd/propagation.hpp"
#include "stvd/voxel_grid_domain.hpp"

namespace stvd::tool {

/// --seed-voxel, --seed-point, --lps, --seeds.
struct SeedOptions {
  std::vector<std::array<int, 3>> seedVoxels;
  std::vector<std::array<double, 3>> seedPoints;
  bool seedPointsInLps = false;
  std::string seedLabels;
};

/// --method, --steiner, --k, --chain-measure, --stencil, --domain-connectivity,
/// --no-memory-check.
struct PropagationChoice {
  Method method = Method::ShortTermVectorDijkstra;
  bool lanthier = false;  // Steiner-point propagation instead of `method`
  int steinerPoints = 0;  // 0: --steiner not given
  int k = kDefaultMemoryDepth;  // the library's defaults: one answer for both
  bool kGiven = false;
  ChainMeasure chainMeasure = kDefaultChainMeasure;
  bool chainMeasureGiven = false;
  std::string stencil = "26";
  bool stencilGiven = false;
  /// --no-memory-check: run even when the estimate exceeds the available memory.
  bool memoryCheck = true;
  /// Which contacts between domain voxels paths may pass (volumes only).
  VoxelConnectivity connectivity = VoxelConnectivity::Faces;
  bool connectivityGiven = false;
};

/// When `option` is a seed option, reads it into `seeds` and returns true.
bool parseSeedOption(const std::string& option, ArgumentReader& args, SeedOptions& seeds);
/// When `option` is a propagation option, reads it into `choice` and returns true.
bool parsePropagationOption(const std::string& option, ArgumentReader& args, PropagationChoice& choice);
/// Usage errors for combinations that make no sense (--k with Dijkstra, a
/// stencil that cannot step across the contacts --domain-connectivity
/// joins, ...). Commands that need predecessors (paths) refuse lanthier,
/// which has none.
void checkPropagationChoice(const PropagationChoice& choice, bool lanthierAllowed);
/// The same rules for the tetrahedral-mesh and surface commands, which have
/// no stencil (parse them with parsePropagationOption but not --stencil)
/// and, as they always have, accept and ignore --k and --chain-measure with
/// dijkstra; --domain-connectivity applies to voxel grids only. `cellEdge`
/// names the edges that carry the Steiner points in messages ("tetrahedron
/// edge", "face edge").
void checkMeshPropagationChoice(const PropagationChoice& choice, const std::string& cellEdge,
                                int suggestedSteinerPoints);
/// The propagation options of the choice (k = 1 for Dijkstra; not lanthier).
PropagationOptions propagationOptions(const PropagationChoice& choice);
/// "STVD with k = 8 (largest-norm chain measure)", "Dijkstra" or the
/// Steiner-point method with its M.
std::string methodText(const PropagationChoice& choice);
/// What the domain's connectivity joins, for summaries: "connectivity 6
/// (voxels joined through faces only)".
std::string connectivityText(VoxelConnectivity connectivity);

/// A voxel the user named, and how (for messages).
struct Seed {
  VoxelIndex index;
  std::string givenAs;  // how the user gave it, for messages
};

std::string voxelText(const VoxelIndex& v);
std::string pointText(const Vec3d& p, int decimals);
Vec3d lpsToRas(const Vec3d& p);

/// The voxels of the seed options: voxels and points must lie in the image
/// and the domain (ToolError kExitDomain naming `role`, "seed" or "target",
/// otherwise); label voxels outside the domain are left out and counted.
std::vector<Seed> resolveSeeds(const std::string& inputPath, const SeedOptions& o, const TensorInput& input,
                               const imaging::MetricOptions& metric, const std::vector<std::uint8_t>& inDomain,
                               std::size_t& labelSeedsLeftOut, const std::string& role = "seed");

}  // namespace stvd::tool
