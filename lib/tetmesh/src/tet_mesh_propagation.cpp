#include "stvd/tetmesh/tet_mesh_propagation.hpp"

#include <optional>
#include <utility>

#include "stvd/cell_mesh/cell_mesh_domain.hpp"
#include "stvd/cell_mesh/cell_mesh_lanthier.hpp"
#include "stvd/cell_mesh/tetrahedral_cells.hpp"
#include "stvd/errors.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/metric/metric_field.hpp"
#include "stvd/tetmesh/vertex_order.hpp"

namespace stvd::tetmesh {

TetrahedraInDomain tetrahedraInDomain(const std::vector<std::array<VertexId, 4>>& tets,
                                      const std::vector<std::uint8_t>& inDomain, const std::string& meshName) {
  TetrahedraInDomain out;
  out.tets.reserve(tets.size());
  for (std::size_t n = 0; n < tets.size(); ++n)
    for (VertexId v : tets[n])
      if (v >= inDomain.size())
        throw InputError(meshName + ": tetrahedron " + std::to_string(n) + " has the corner " + std::to_string(v) +
                         ", but there are " + std::to_string(inDomain.size()) + " vertices");
  for (const auto& t : tets)
    if (inDomain[t[0]] && inDomain[t[1]] && inDomain[t[2]] && inDomain[t[3]]) out.tets.push_back(t);
  if (out.tets.empty())
    throw NothingToCompute(meshName + ": the domain is empty: no tetrahedron has four usable vertices");
  out.covered.assign(inDomain.size(), 0);
  for (const auto& t : out.tets)
    for (VertexId v : t) out.covered[v] = 1;
  return out;
}

TetMeshPropagation propagateOverTetrahedra(const std::vector<Vec3d>& points,
                                           const std::vector<std::array<VertexId, 4>>& tets,
                                           const std::vector<SymTensor3>& metricTensors,
                                           const std::vector<std::uint8_t>& inDomain,
                                           const std::vector<VertexId>& sources, const PropagationChoice& choice,
                                           double maxDistance, const std::string& meshName,
                                           std::function<bool(const PropagationProgress&)> progress) {
  const VertexPermutation order = mortonOrder(points);
  std::vector<SymTensor3> orderedTensors(points.size());
  std::vector<std::uint8_t> orderedInDomain(points.size());
  for (std::size_t n = 0; n < points.size(); ++n) {
    orderedTensors[n] = metricTensors[order.newToOld[n]];
    orderedInDomain[n] = inDomain[order.newToOld[n]];
  }
  std::vector<VertexId> orderedSources;
  for (VertexId v : sources) orderedSources.push_back(order.oldToNew[v]);

  TetMeshPropagation out;
  const std::vector<Vec3d> orderedPoints = permutedPoints(points, order);
  const std::vector<CellMeshDomain::Tetrahedron> orderedTets = permutedTets(tets, order);
  const RiemannianMetric metric(std::move(orderedTensors), &orderedInDomain);
  PropagationResult result;
  if (choice.lanthier) {
    // The cells are the domain's tetrahedra (those with four usable
    // corners), so vertices outside the domain are never reached.
    std::optional<TetrahedralCells> cells;
    try {
      cells.emplace(orderedPoints, orderedTets);
    } catch (const std::invalid_argument& e) {  // e.g. a face shared by more than two tetrahedra
      throw InputError(meshName + ": " + e.what());
    }
    out.edgeCount = cells->edges().size();
    LanthierOptions steiner;
    steiner.steinerPoints = choice.steinerPoints;
    steiner.maxDistance = maxDistance;
    steiner.progress = std::move(progress);
    try {
      result = lanthierPropagate(*cells, metric, orderedSources, steiner);
    } catch (const std::invalid_argument& e) {  // too large a graph for 32-bit point numbers
      throw OptionError(meshName + ": --method lanthier: " + e.what());
    }
  } else {
    // The edges for the propagation, and the tetrahedra that STVD walks its
    // candidates' segments through (refused where they leave the domain).
    std::optional<CellMeshDomain> domain;
    try {
      domain.emplace(CellMeshDomain::fromTetrahedra(orderedPoints, orderedTets));
    } catch (const std::invalid_argument& e) {  // a face shared by more than two tetrahedra
      throw InputError(meshName + ": " + e.what());
    }
    out.edgeCount = domain->edgeCount();
    PropagationOptions options = propagationOptions(choice);
    options.maxDistance = maxDistance;
    options.progress = std::move(progress);
    result = propagate(*domain, metric, orderedSources, options);
  }

  // Back to the caller's numbering.
  out.result = result;
  for (std::size_t v = 0; v < points.size(); ++v) {
    const VertexId n = order.oldToNew[v];
    out.result.distance[v] = result.distance[n];
    const VertexId p = result.predecessor[n];
    out.result.predecessor[v] = p == kNoVertex ? kNoVertex : order.newToOld[p];
  }
  return out;
}

}  // namespace stvd::tetmesh
