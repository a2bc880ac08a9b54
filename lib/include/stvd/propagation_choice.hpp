// How stvd's front ends (the command-line tool and the Python package) name,
// check and default a propagation: the method, Lanthier's Steiner points,
// STVD's memory depth and chain measure, and the grid stencil. Both go
// through this one place, so that their defaults and their messages agree.
#pragma once

#include <string>

#include "stvd/front_end_errors.hpp"
#include "stvd/propagation.hpp"

namespace stvd {

/// The front ends measure STVD's chain sums with the largest edge norm on the
/// chain, not with the paper's projection-weighted rule (the core's
/// default): real DTI tensor fields vary strongly from voxel to voxel, and
/// there the paper's rule lets backward portions cancel forward ones, so
/// distances collapse as k grows (on the shipped brain, k = 8 puts 44,000
/// to 70,000 voxels below the bound |x - seed|/sqrt(3) that G = (D/MD)^-1
/// guarantees). The largest-norm rule cannot cancel; with it the median
/// difference to Dijkstra on the 290-offset stencil settles at +1.7 to
/// +2.2 % from k = 8 on (docs/cli.md, "Chain measure and k").
inline constexpr ChainMeasure kFrontEndChainMeasure = ChainMeasure::LargestEdgeNorm;
inline constexpr int kFrontEndMemoryDepth = 8;
/// Surfaces keep the paper's rule by default (docs/surfaces.md).
inline constexpr ChainMeasure kSurfaceChainMeasure = ChainMeasure::ProjectionWeighted;

/// What the front ends' distance maps hold where no distance was reached
/// (-1, which no distance can take; --unreachable-value changes it).
inline constexpr double kFrontEndUnreachableValue = -1.0;

/// A propagation as a front end's user chose it (--method, --steiner, --k,
/// --chain-measure, --stencil), with the front ends' defaults; the *Given
/// flags record what was stated, for the checks below.
struct PropagationChoice {
  Method method = Method::ShortTermVectorDijkstra;
  bool lanthier = false;  // Steiner-point propagation instead of `method`
  int steinerPoints = 0;  // 0: not given
  int k = kFrontEndMemoryDepth;
  bool kGiven = false;
  ChainMeasure chainMeasure = kFrontEndChainMeasure;
  bool chainMeasureGiven = false;
  std::string stencil = "26";
  bool stencilGiven = false;
};

// The setters take a value as the user gave it and throw OptionError with
// the tool's message when it is not one of the accepted ones.

/// "stvd", "dijkstra" or "lanthier".
void setMethod(PropagationChoice& choice, const std::string& name);
/// 1..kMaxSteinerPoints.
void setSteinerPoints(PropagationChoice& choice, int points);
/// 1..kMaxMemoryDepth.
void setMemoryDepth(PropagationChoice& choice, int k);
/// "largest" or "projection".
void setChainMeasure(PropagationChoice& choice, const std::string& name);
/// "6", "18", "26", "98" or "290" (Stencil::byName).
void setStencil(PropagationChoice& choice, const std::string& name);

/// OptionError for combinations that make no sense on a voxel grid (--k with
/// Dijkstra, --stencil with lanthier, lanthier without --steiner, ...).
/// Commands that need predecessors (paths, connectivity) refuse lanthier,
/// which has none.
void checkPropagationChoice(const PropagationChoice& choice, bool lanthierAllowed);
/// The same rules for tetrahedral meshes and surfaces, which have no stencil
/// and, as they always have, accept and ignore --k and --chain-measure with
/// dijkstra. `cellEdge` names the edges that carry the Steiner points in
/// messages ("tetrahedron edge", "face edge").
void checkMeshPropagationChoice(const PropagationChoice& choice, const std::string& cellEdge,
                                int suggestedSteinerPoints);

/// The propagation options of the choice (k = 1 for Dijkstra; not lanthier).
PropagationOptions propagationOptions(const PropagationChoice& choice);
/// "STVD with k = 8 (largest-norm chain measure)", "Dijkstra" or the
/// Steiner-point method with its M.
std::string methodText(const PropagationChoice& choice);
/// "stvd", "dijkstra" or "lanthier".
std::string methodName(const PropagationChoice& choice);
/// "largest" or "projection".
std::string chainMeasureName(ChainMeasure measure);

}  // namespace stvd
