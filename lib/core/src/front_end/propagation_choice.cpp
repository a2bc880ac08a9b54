#include "stvd/front_end/propagation_choice.hpp"

#include <cmath>
#include <limits>

#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/voxel_grid/stencil.hpp"

namespace stvd {

void setMethod(PropagationChoice& o, const std::string& m) {
  o.lanthier = m == "lanthier";
  if (m == "stvd")
    o.method = Method::ShortTermVectorDijkstra;
  else if (m == "dijkstra")
    o.method = Method::Dijkstra;
  else if (!o.lanthier)
    throw OptionError("--method: '" + m + "' is not one of stvd, dijkstra, lanthier");
}

void setSteinerPoints(PropagationChoice& o, int points) {
  o.steinerPoints = points;
  if (o.steinerPoints < 1 || o.steinerPoints > kMaxSteinerPoints)
    throw OptionError("--steiner must be between 1 and " + std::to_string(kMaxSteinerPoints));
}

void setMemoryDepth(PropagationChoice& o, int k) {
  o.k = k;
  if (k < 1 || k > kMaxMemoryDepth)
    throw OptionError("--k must be between 1 and " + std::to_string(kMaxMemoryDepth));
}

void setChainMeasure(PropagationChoice& o, const std::string& m) {
  if (m == "segment")
    o.chainMeasure = ChainMeasure::Segment;
  else if (m == "projection")
    o.chainMeasure = ChainMeasure::ProjectionWeighted;
  else if (m == "largest")
    o.chainMeasure = ChainMeasure::LargestEdgeNorm;
  else
    throw OptionError("--chain-measure: '" + m + "' is not one of segment, projection, largest");
  o.chainMeasureGiven = true;
}

void setStencil(PropagationChoice& o, const std::string& name) {
  o.stencil = name;
  o.stencilGiven = true;
  try {
    Stencil::byName(o.stencil);
  } catch (const std::invalid_argument&) {
    throw OptionError("--stencil: '" + o.stencil + "' is not one of 6, 18, 26, 98, 290");
  }
}

void setDomainConnectivity(PropagationChoice& o, const std::string& c) {
  if (c == "6")
    o.connectivity = VoxelConnectivity::Faces;
  else if (c == "18")
    o.connectivity = VoxelConnectivity::Edges;
  else if (c == "26")
    o.connectivity = VoxelConnectivity::Corners;
  else
    throw OptionError("--domain-connectivity: '" + c + "' is not one of 6, 18, 26");
  o.connectivityGiven = true;
}

namespace {

/// The rules every domain shares: STVD's options are refused where no
/// STVD runs (`stvdOnly`: every method but stvd; otherwise lanthier only),
/// and --steiner goes with lanthier and lanthier needs it.
void checkCommonChoice(const PropagationChoice& o, bool stvdOnly, const std::string& cellEdge,
                       int suggestedSteinerPoints) {
  const bool refuseStvdOptions = stvdOnly ? (o.lanthier || o.method != Method::ShortTermVectorDijkstra) : o.lanthier;
  if (o.k && refuseStvdOptions) throw OptionError("--k applies to --method stvd only");
  if (o.chainMeasureGiven && refuseStvdOptions) throw OptionError("--chain-measure applies to --method stvd only");
  if (o.lanthier && o.steinerPoints == 0)
    throw OptionError("--method lanthier needs --steiner M, the Steiner points per " + cellEdge + " (1.." +
                      std::to_string(kMaxSteinerPoints) + "; try " + std::to_string(suggestedSteinerPoints) + ")");
  if (!o.lanthier && o.steinerPoints != 0) throw OptionError("--steiner applies to --method lanthier only");
}

}  // namespace

void checkPropagationChoice(const PropagationChoice& o, bool lanthierAllowed) {
  if (o.lanthier && !lanthierAllowed)
    throw OptionError(
        "--method lanthier gives distances but no predecessors, which paths need; use stvd or dijkstra");
  checkCommonChoice(o, /*stvdOnly=*/true, "cube edge", 2);
  if (o.lanthier && o.stencilGiven) throw OptionError("--stencil does not apply to --method lanthier (it uses cubes)");
  // Every method must reach the same voxels: a stencil has to contain the
  // steps across the contacts that the connectivity joins (the 98 and 290
  // stencils contain all 26 unit steps).
  if (!o.lanthier) {
    const bool edgeSteps = o.stencil != "6", cornerSteps = edgeSteps && o.stencil != "18";
    if (o.connectivity == VoxelConnectivity::Edges && !edgeSteps)
      throw OptionError("--domain-connectivity 18 joins voxels that touch along an edge, which the 6-neighbour "
                        "stencil cannot step between; use --stencil 18 or larger");
    if (o.connectivity == VoxelConnectivity::Corners && !cornerSteps)
      throw OptionError("--domain-connectivity 26 joins voxels that touch at a corner, which the " + o.stencil +
                        "-neighbour stencil cannot step between; use --stencil 26 or larger");
  }
}

void checkMeshPropagationChoice(const PropagationChoice& o, const std::string& cellEdge, int suggestedSteinerPoints) {
  checkCommonChoice(o, /*stvdOnly=*/false, cellEdge, suggestedSteinerPoints);
  if (o.connectivityGiven) throw OptionError("--domain-connectivity applies to voxel grids only");
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

void checkUnreachableValue(double value, const std::string& given) {
  if (!std::isnan(value) && !(std::abs(value) <= std::numeric_limits<float>::max()))
    throw OptionError("--unreachable-value: '" + given + "' does not fit in a float32 map (magnitude at most 3.4e38)");
}

}  // namespace stvd
