#include "stvd/front_end/propagation_choice.hpp"

#include <cmath>
#include <limits>

#include "stvd/front_end/propagation_choice_options.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/voxel_grid/stencil.hpp"

namespace stvd {

namespace {

/// Checks `value` as the option's declaration says and sets it.
void setOption(PropagationChoice& choice, const std::string& flag, OptionValue value) {
  applyPropagationOption(choice, flag, checkOptionValue(propagationOption(flag), std::move(value), choice.naming));
}

}  // namespace

void setMethod(PropagationChoice& o, const std::string& m) { setOption(o, "--method", m); }
void setSteinerPoints(PropagationChoice& o, int points) { setOption(o, "--steiner", static_cast<long long>(points)); }
void setMemoryDepth(PropagationChoice& o, int k) { setOption(o, "--k", static_cast<long long>(k)); }
void setChainMeasure(PropagationChoice& o, const std::string& m) { setOption(o, "--chain-measure", m); }
void setStencil(PropagationChoice& o, const std::string& name) { setOption(o, "--stencil", name); }
void setDomainConnectivity(PropagationChoice& o, const std::string& c) { setOption(o, "--domain-connectivity", c); }

namespace {

/// How the choice's messages name an option, and an option with a value.
std::string name(const PropagationChoice& o, const std::string& flag) {
  return optionName(propagationOption(flag), o.naming);
}
std::string named(const PropagationChoice& o, const std::string& flag, const std::string& value) {
  return optionWithValue(propagationOption(flag), value, o.naming);
}

/// The rules every domain shares: STVD's options are refused where no
/// STVD runs (`stvdOnly`: every method but stvd; otherwise lanthier only),
/// and --steiner goes with lanthier and lanthier needs it.
void checkCommonChoice(const PropagationChoice& o, bool stvdOnly, const std::string& cellEdge,
                       int suggestedSteinerPoints) {
  const bool refuseStvdOptions = stvdOnly ? (o.lanthier || o.method != Method::ShortTermVectorDijkstra) : o.lanthier;
  const std::string onlyWithStvd = " applies to " + named(o, "--method", "stvd") + " only";
  if (o.k && refuseStvdOptions) throw OptionError(name(o, "--k") + onlyWithStvd);
  if (o.chainMeasureGiven && refuseStvdOptions) throw OptionError(name(o, "--chain-measure") + onlyWithStvd);
  if (o.lanthier && o.steinerPoints == 0)
    throw OptionError(named(o, "--method", "lanthier") + " needs " + named(o, "--steiner", "M") +
                      ", the Steiner points per " + cellEdge + " (" + optionRangeText(propagationOption("--steiner")) +
                      "; try " + std::to_string(suggestedSteinerPoints) + ")");
  if (!o.lanthier && o.steinerPoints != 0)
    throw OptionError(name(o, "--steiner") + " applies to " + named(o, "--method", "lanthier") + " only");
}

}  // namespace

void checkPropagationChoice(const PropagationChoice& o, bool lanthierAllowed) {
  if (o.lanthier && !lanthierAllowed)
    throw OptionError(named(o, "--method", "lanthier") +
                      " gives distances but no predecessors, which paths need; use stvd or dijkstra");
  checkCommonChoice(o, /*stvdOnly=*/true, "cube edge", 2);
  if (o.lanthier && o.stencilGiven)
    throw OptionError(name(o, "--stencil") + " does not apply to " + named(o, "--method", "lanthier") +
                      " (it uses cubes)");
  // Every method must reach the same voxels: a stencil has to contain the
  // steps across the contacts that the connectivity joins (the 98 and 290
  // stencils contain all 26 unit steps).
  if (!o.lanthier) {
    const bool edgeSteps = o.stencil != "6", cornerSteps = edgeSteps && o.stencil != "18";
    if (o.connectivity == VoxelConnectivity::Edges && !edgeSteps)
      throw OptionError(named(o, "--domain-connectivity", "18") +
                        " joins voxels that touch along an edge, which the 6-neighbour stencil cannot step between; "
                        "use " + named(o, "--stencil", "18") + " or larger");
    if (o.connectivity == VoxelConnectivity::Corners && !cornerSteps)
      throw OptionError(named(o, "--domain-connectivity", "26") + " joins voxels that touch at a corner, which the " +
                        o.stencil + "-neighbour stencil cannot step between; use " + named(o, "--stencil", "26") +
                        " or larger");
  }
}

void checkMeshPropagationChoice(const PropagationChoice& o, const std::string& cellEdge, int suggestedSteinerPoints) {
  checkCommonChoice(o, /*stvdOnly=*/false, cellEdge, suggestedSteinerPoints);
  if (o.connectivityGiven)
    throw OptionError(name(o, "--domain-connectivity") + " " + propagationOption("--domain-connectivity").refusal);
}

PropagationOptions propagationOptions(const PropagationChoice& o) {
  PropagationOptions options;
  options.method = o.method;
  options.k = o.method == Method::Dijkstra ? std::optional<int>(1) : o.k;
  options.chainMeasure = o.chainMeasure;
  return options;
}

std::string methodText(const PropagationChoice& o, int k) {
  if (o.lanthier)
    return "Lanthier Steiner-point propagation with M = " + std::to_string(o.steinerPoints) + " points per cube edge";
  if (o.method == Method::Dijkstra) return "Dijkstra";
  const char* measure = o.chainMeasure == ChainMeasure::Segment            ? " (segment measure)"
                        : o.chainMeasure == ChainMeasure::LargestEdgeNorm ? " (largest-norm chain measure)"
                                                                          : " (projection chain measure)";
  return "STVD with k = " + std::to_string(k) + measure;
}

std::string methodName(const PropagationChoice& o) {
  return o.lanthier ? "lanthier" : o.method == Method::Dijkstra ? "dijkstra" : "stvd";
}

std::string connectivityText(VoxelConnectivity c) {
  switch (c) {
    case VoxelConnectivity::Faces: return "domain connectivity 6 (voxels joined through faces only)";
    case VoxelConnectivity::Edges: return "domain connectivity 18 (voxels also joined across edge contacts)";
    case VoxelConnectivity::Corners:
      return "domain connectivity 26 (voxels also joined across edge and corner contacts)";
  }
  return "?";
}

void checkUnreachableValue(double value, const std::string& given, OptionNaming naming) {
  const OptionDeclaration& option = propagationOption("--unreachable-value");
  option.extraCheck(value, optionName(option, naming), given);
}

}  // namespace stvd
