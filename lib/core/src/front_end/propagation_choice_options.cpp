#include "stvd/front_end/propagation_choice_options.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "stvd/cell_mesh/cell_mesh_propagation.hpp"
#include "stvd/errors.hpp"
#include "stvd/lanthier/lanthier_propagation.hpp"
#include "stvd/surface/surface_propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace stvd {
namespace {

/// The same default on every kind of domain.
std::array<OptionValue, 3> everywhere(const OptionValue& value) { return {value, value, value}; }

void checkFitsFloat32Map(const OptionValue& value, const std::string& name, const std::string& given) {
  const double x = std::get<double>(value);
  if (!std::isnan(x) && !(std::abs(x) <= std::numeric_limits<float>::max()))
    throw OptionError(name + ": '" + given + "' does not fit in a float32 map (magnitude at most 3.4e38)");
}

std::vector<OptionDeclaration> declarations() {
  const PropagationChoice defaults;
  std::vector<OptionDeclaration> table;

  OptionDeclaration method;
  method.flag = "--method";
  method.valueName = "M";
  method.keyword = "method";
  method.type = OptionType::Choice;
  method.group = OptionGroup::Propagation;
  method.commands = kVolumeCommands | kMeshCommands | kCohortCommand;
  method.choices = {
      {"stvd", "Short-Term Vector Dijkstra (Campen et al. 2013)"},
      {"dijkstra", "shortest paths along the edges of the stencil or the mesh"},
      {"lanthier",
       "Steiner points on the cells between the vertices (voxel cubes, faces, tetrahedra), the slow "
       "accurate reference; needs --steiner, gives distances only (docs/steiner.md)"}};
  method.choiceLayout = ChoiceLayout::Lines;
  method.help = "{choices}.";
  method.defaults = everywhere(methodName(defaults));
  table.push_back(method);

  OptionDeclaration steiner;
  steiner.flag = "--steiner";
  steiner.valueName = "M";
  steiner.keyword = "steiner";
  steiner.type = OptionType::Integer;
  steiner.group = OptionGroup::Propagation;
  steiner.commands = kDistanceCommand | kMeshCommands;
  steiner.range = {1.0, double(kMaxSteinerPoints)};
  // Commands that trace paths have no use for it (lanthier gives no
  // predecessors) and say so.
  steiner.refusedBy = kPathCommand | kConnectivityCommand;
  steiner.refusal = "applies to --method lanthier only, which gives distances but no paths";
  steiner.help =
      "lanthier: Steiner points per cube edge, {range}; time and memory grow like M^4 and M^2 (shipped "
      "brain: M = 2 3 s, M = 8 4 min and 450 MB; docs/steiner.md).";
  steiner.helpFor = {
      {kSurfaceDistanceCommand, "lanthier: Steiner points per face edge, {range}; time grows like M^2, memory like M."},
      {kTetMeshDistanceCommand,
       "lanthier: Steiner points per tetrahedron edge, {range} (also on the faces, joined through each "
       "tetrahedron)."}};
  table.push_back(steiner);

  OptionDeclaration k;
  k.flag = "--k";
  k.valueName = "N";
  k.keyword = "k";
  k.type = OptionType::Integer;
  k.group = OptionGroup::Propagation;
  k.commands = kVolumeCommands | kMeshCommands | kCohortCommand;
  k.range = {1.0, double(kMaxMemoryDepth)};
  k.help = "STVD memory depth, {range} (default {default}; see docs/cli.md).";
  // Each kind of domain has its own: surfaces need longer chains.
  k.defaults = {static_cast<long long>(defaultMemoryDepth<VoxelGridDomain>()),
                static_cast<long long>(defaultMemoryDepth<SurfaceDomain>()),
                static_cast<long long>(defaultMemoryDepth<CellMeshDomain>())};
  table.push_back(k);

  OptionDeclaration chain;
  chain.flag = "--chain-measure";
  chain.valueName = "R";
  chain.keyword = "chain_measure";
  chain.type = OptionType::Choice;
  chain.group = OptionGroup::Propagation;
  chain.commands = kVolumeCommands | kMeshCommands | kCohortCommand;
  for (const ChainMeasure m : {ChainMeasure::Segment, ChainMeasure::ProjectionWeighted, ChainMeasure::LargestEdgeNorm})
    chain.choices.push_back({chainMeasureName(m), ""});
  chain.choices[0].help =
      "its straight segment, measured along itself with the metric where it runs, used only inside the domain";
  chain.choices[1].help = "the paper's rule, which underestimates on DTI data for k > 3";
  chain.choices[2].help = "the most expensive edge norm on the chain";
  chain.help = "how STVD measures a candidate: {choices}; see docs/cli.md.";
  chain.defaults = everywhere(std::string(chainMeasureName(kDefaultChainMeasure)));
  table.push_back(chain);

  OptionDeclaration stencil;
  stencil.flag = "--stencil";
  stencil.valueName = "S";
  stencil.keyword = "stencil";
  stencil.type = OptionType::Choice;
  stencil.group = OptionGroup::Propagation;
  stencil.commands = kVolumeCommands | kCohortCommand;
  stencil.choices = {{"6", ""}, {"18", ""}, {"26", ""}, {"98", "5x5x5"}, {"290", "7x7x7"}};
  stencil.help = "neighbourhood: {choices}.";
  stencil.defaults = everywhere(defaults.stencil);
  table.push_back(stencil);

  OptionDeclaration connectivity;
  connectivity.flag = "--domain-connectivity";
  connectivity.valueName = "C";
  connectivity.keyword = "domain_connectivity";
  connectivity.keywordTakesNumber = true;
  connectivity.type = OptionType::Choice;
  connectivity.group = OptionGroup::Propagation;
  connectivity.commands = kVolumeCommands;
  connectivity.choices = {
      {"6",
       "only through the cells between voxel centres whose corners are all in the domain, so no path passes a "
       "gap of zero width"},
      {"18", "also two voxels that share only an edge"},
      {"26", "also two that share only a corner"}};
  connectivity.help =
      "which domain voxels touch, with a mask or --fa-threshold: {choices}. Every method keeps to it, and paths "
      "keep to the same region as the distances (docs/cli.md).";
  connectivity.defaults = everywhere(static_cast<long long>(defaults.connectivity));
  connectivity.refusedBy = kMeshCommands;
  connectivity.refusal = "applies to voxel grids only";
  table.push_back(connectivity);

  OptionDeclaration maxDistance;
  maxDistance.flag = "--max-distance";
  maxDistance.valueName = "D";
  maxDistance.keyword = "max_distance";
  maxDistance.type = OptionType::Number;
  maxDistance.group = OptionGroup::Propagation;
  maxDistance.commands = kDistanceCommand | kMeshCommands | kCohortCommand;
  maxDistance.range.min = 0.0;
  maxDistance.range.minExcluded = true;
  maxDistance.keywordAcceptsInfinity = true;  // max_distance=math.inf: no limit, as None
  maxDistance.help = "stop at D mm; farther voxels are unreachable.";
  maxDistance.helpFor = {{kMeshCommands, "stop at D (mesh units); farther vertices are unreachable."}};
  table.push_back(maxDistance);

  OptionDeclaration memoryCheck;
  memoryCheck.flag = "--no-memory-check";
  memoryCheck.keyword = "memory_check";
  memoryCheck.keywordIsNegation = true;
  memoryCheck.type = OptionType::Switch;
  memoryCheck.group = OptionGroup::Propagation;
  memoryCheck.commands = kVolumeCommands | kMeshCommands;
  memoryCheck.help =
      "run even when the estimate of the memory the run needs exceeds the memory available (exit code 6 "
      "otherwise).";
  memoryCheck.helpFor = {{kConnectivityCommand,
                          "run even when the memory the propagations need (one per thread) exceeds the memory "
                          "available (exit code 6 otherwise)."}};
  table.push_back(memoryCheck);

  OptionDeclaration unreachable;
  unreachable.flag = "--unreachable-value";
  unreachable.valueName = "V";
  unreachable.keyword = "unreachable_value";
  unreachable.keywordCommands = kDistanceCommand | kMeshCommands | kCohortCommand;
  unreachable.type = OptionType::Number;
  unreachable.acceptsNan = true;
  unreachable.extraCheck = checkFitsFloat32Map;
  unreachable.group = OptionGroup::Output;
  unreachable.commands = kDistanceCommand | kTetMeshDistanceCommand | kCohortCommand;
  unreachable.help =
      "value of voxels not reached: a number or nan (default {default}; nan keeps them out of mrstats and most "
      "viewers' statistics).";
  unreachable.helpFor = {{kTetMeshDistanceCommand, "distance of vertices not reached: a number or nan (default {default})."}};
  unreachable.defaults = everywhere(kDefaultUnreachableValue);
  table.push_back(unreachable);
  return table;
}

}  // namespace

const std::vector<OptionDeclaration>& propagationOptionDeclarations() {
  static const std::vector<OptionDeclaration> table = declarations();
  return table;
}

const OptionDeclaration& propagationOption(const std::string& flag) {
  const OptionDeclaration* option = findOption(propagationOptionDeclarations(), flag);
  if (!option) throw std::logic_error("no propagation option " + flag);
  return *option;
}

void applyPropagationOption(PropagationChoice& choice, const std::string& flag, const OptionValue& value) {
  if (flag == "--method") {
    const std::string& method = std::get<std::string>(value);
    choice.lanthier = method == "lanthier";
    choice.method = method == "dijkstra" ? Method::Dijkstra : Method::ShortTermVectorDijkstra;
  } else if (flag == "--steiner") {
    choice.steinerPoints = static_cast<int>(std::get<long long>(value));
  } else if (flag == "--k") {
    choice.k = static_cast<int>(std::get<long long>(value));
  } else if (flag == "--chain-measure") {
    for (const ChainMeasure m : {ChainMeasure::Segment, ChainMeasure::ProjectionWeighted, ChainMeasure::LargestEdgeNorm})
      if (std::get<std::string>(value) == chainMeasureName(m)) choice.chainMeasure = m;
    choice.chainMeasureGiven = true;
  } else if (flag == "--stencil") {
    choice.stencil = std::get<std::string>(value);
    choice.stencilGiven = true;
  } else if (flag == "--domain-connectivity") {
    choice.connectivity = static_cast<VoxelConnectivity>(std::stoi(std::get<std::string>(value)));
    choice.connectivityGiven = true;
  } else if (flag == "--no-memory-check") {
    choice.memoryCheck = false;
  }
}

PropagationChoice propagationChoiceOf(const OptionValues& values) {
  PropagationChoice choice;
  choice.naming = values.naming();
  for (const OptionDeclaration& option : propagationOptionDeclarations())
    for (const OptionValue& value : values.all(option.flag)) applyPropagationOption(choice, option.flag, value);
  return choice;
}

}  // namespace stvd
