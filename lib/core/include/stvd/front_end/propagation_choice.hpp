// How stvd's front ends (the command-line tool and the Python package) name,
// check and default a propagation: the method, Lanthier's Steiner points,
// STVD's memory depth and chain measure, and the grid stencil. Both go
// through this one place, so that their defaults (the library's own:
// kDefaultChainMeasure, and per kind of domain defaultMemoryDepth) and their
// messages agree.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "stvd/errors.hpp"
#include "stvd/front_end/option_declarations.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

namespace stvd {

/// What the front ends' distance maps hold where no distance was reached,
/// unless told otherwise (the tool's --unreachable-value, the Python
/// package's unreachable_value=): -1, which no distance can take. The
/// library itself leaves such vertices at kUnreachable (+infinity).
inline constexpr double kDefaultUnreachableValue = -1.0;

/// A propagation as a front end's user chose it (--method, --steiner, --k,
/// --chain-measure, --stencil, --domain-connectivity, --no-memory-check),
/// with the library's
/// defaults; what was stated is kept apart from the defaults, for the checks
/// below.
struct PropagationChoice {
  Method method = Method::ShortTermVectorDijkstra;
  bool lanthier = false;  // Steiner-point propagation instead of `method`
  int steinerPoints = 0;  // 0: not given
  /// Unset: the domain's default (defaultMemoryDepth<Domain>()), which the
  /// propagation takes itself.
  std::optional<int> k;
  ChainMeasure chainMeasure = kDefaultChainMeasure;
  bool chainMeasureGiven = false;
  std::string stencil = "26";
  bool stencilGiven = false;
  /// Which contacts between domain voxels paths may pass (voxel grids only;
  /// VoxelGridDomain's default).
  VoxelConnectivity connectivity = VoxelConnectivity::Faces;
  bool connectivityGiven = false;
  /// Whether the memory the run needs is compared with the memory available
  /// before it starts (stvd/system/memory.hpp; --no-memory-check: false).
  bool memoryCheck = true;
  /// How the checks below name options in their messages: the tool's
  /// flags, or the Python package's keywords.
  OptionNaming naming = OptionNaming::Flags;
};

// The setters take a value as the user gave it and throw OptionError with
// the tool's message when it is not one of the accepted ones (the checks of
// the options' declarations, stvd/front_end/propagation_choice_options.hpp, which
// the front ends use themselves through propagationChoiceOf).

/// "stvd", "dijkstra" or "lanthier".
void setMethod(PropagationChoice& choice, const std::string& name);
/// 1..kMaxSteinerPoints.
void setSteinerPoints(PropagationChoice& choice, int points);
/// 1..kMaxMemoryDepth.
void setMemoryDepth(PropagationChoice& choice, int k);
/// "segment", "projection" or "largest" (chainMeasureName).
void setChainMeasure(PropagationChoice& choice, const std::string& name);
/// "6", "18", "26", "98" or "290" (Stencil::byName).
void setStencil(PropagationChoice& choice, const std::string& name);
/// "6", "18" or "26" (VoxelConnectivity).
void setDomainConnectivity(PropagationChoice& choice, const std::string& name);

/// OptionError for combinations that make no sense on a voxel grid (--k with
/// Dijkstra, --stencil with lanthier, lanthier without --steiner, a stencil
/// that cannot step across the contacts --domain-connectivity joins, ...).
/// Commands that need predecessors (paths, connectivity) refuse lanthier,
/// which has none.
void checkPropagationChoice(const PropagationChoice& choice, bool lanthierAllowed);
/// The same rules for tetrahedral meshes and surfaces, which have no stencil
/// and, as they always have, accept and ignore --k and --chain-measure with
/// dijkstra; --domain-connectivity applies to voxel grids only. `cellEdge`
/// names the edges that carry the Steiner points in messages ("tetrahedron
/// edge", "face edge").
void checkMeshPropagationChoice(const PropagationChoice& choice, const std::string& cellEdge,
                                int suggestedSteinerPoints);

/// The propagation options of the choice (k = 1 for Dijkstra, the stated k
/// or none for STVD; not lanthier).
PropagationOptions propagationOptions(const PropagationChoice& choice);
/// The memory depth a propagation of the choice runs with over a Domain: 1
/// for Dijkstra, the stated k or the domain's default for STVD.
template <class Domain>
int memoryDepthOf(const PropagationChoice& choice) {
  return memoryDepth<Domain>(propagationOptions(choice));
}
/// "STVD with k = 6 (segment measure)", "Dijkstra" or the Steiner-point
/// method with its M on a voxel grid; `k` is memoryDepthOf the domain.
std::string methodText(const PropagationChoice& choice, int k);
/// "stvd", "dijkstra" or "lanthier".
std::string methodName(const PropagationChoice& choice);
/// What the domain's connectivity joins, for summaries: "domain connectivity
/// 6 (voxels joined through faces only)".
std::string connectivityText(VoxelConnectivity connectivity);

/// OptionError ("--unreachable-value: '1e+300' does not fit in a float32
/// map ...") unless `value` is NaN or a number a float32 map can hold (1e300
/// would become infinity there); `given` is the value as the user wrote it.
void checkUnreachableValue(double value, const std::string& given, OptionNaming naming = OptionNaming::Flags);

}  // namespace stvd
