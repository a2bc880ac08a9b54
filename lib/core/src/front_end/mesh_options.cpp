#include "stvd/front_end/mesh_options.hpp"

#include <stdexcept>

#include "stvd/errors.hpp"

namespace stvd {
namespace {

std::vector<OptionDeclaration> declarations() {
  std::vector<OptionDeclaration> table;

  OptionDeclaration vertex;
  vertex.flag = "--seed-vertex";
  vertex.valueName = "N";
  vertex.keyword = "seeds";
  vertex.type = OptionType::Index;
  vertex.group = OptionGroup::Seeds;
  vertex.commands = kMeshCommands;
  vertex.repeatable = true;
  vertex.help = "vertex index, counted from 0 in file order (repeatable).";
  vertex.helpFor = {{kTetMeshDistanceCommand, "vertex number N as the .node file numbers it (repeatable)."}};
  table.push_back(vertex);

  OptionDeclaration region;
  region.flag = "--seed-region";
  region.valueName = "NAME";
  region.keyword = "seed_regions";
  region.keywordCommands = kNoCommand;
  region.type = OptionType::Text;
  region.group = OptionGroup::Seeds;
  region.commands = kSurfaceDistanceCommand;
  region.repeatable = true;
  region.help =
      "the vertices of the region NAME of the --seeds annotation (.annot) or GIfTI label file (.label.gii) "
      "are seeds (repeatable: their union).";
  table.push_back(region);

  OptionDeclaration seedAt;
  seedAt.flag = "--seed-at";
  seedAt.valueName = "W";
  seedAt.type = OptionType::Choice;
  seedAt.group = OptionGroup::Seeds;
  seedAt.commands = kMeshCommands;
  seedAt.choices = {{"vertex", "--seed-point snaps to the nearest vertex"},
                    {"point",
                     "the point itself is the seed, inserted as a vertex (into its face or onto its edge on a "
                     "surface, splitting its tetrahedron into four in a tetrahedral mesh), its metric the "
                     "barycentric mean of the corners'"}};
  seedAt.choiceLayout = ChoiceLayout::Lines;
  seedAt.help = "{choices}; outputs still list the file's vertices only.";
  seedAt.defaults = {std::monostate{}, std::string("vertex"), std::string("vertex")};
  table.push_back(seedAt);

  OptionDeclaration metric;
  metric.flag = "--metric";
  metric.valueName = "M";
  metric.keyword = "metric";
  metric.type = OptionType::Choice;
  metric.group = OptionGroup::SurfaceMetric;
  metric.commands = kSurfaceDistanceCommand;
  metric.choices = {
      {"isotropic", "surface distance"},
      {"curvature",
       "principal-curvature tensors, a unit step across the direction of larger curvature costs up to G "
       "(--anisotropy)"},
      {"field:FILE",
       "one direction \"dx dy dz\" per vertex (world frame), a unit step along it costs 1, across it G "
       "(--anisotropy)"},
      {"tensors:FILE",
       "one 3D tensor \"xx xy xz yy yz zz\" per vertex (world frame), projected to the tangent plane"},
      {"face-tensors:FILE", "the same per face (file order), averaged to the vertices by corner angle"},
      {"scale:FILE",
       "one positive number per vertex (.func.gii, .shape.gii, curv, .mgh, .mgz or a text column): a unit step "
       "near the vertex costs that much (isotropic)"}};
  metric.choiceLayout = ChoiceLayout::Lines;
  metric.help = "{choices}.";
  metric.defaults = {std::monostate{}, std::string("isotropic"), std::monostate{}};
  table.push_back(metric);

  OptionDeclaration anisotropy;
  anisotropy.flag = "--anisotropy";
  anisotropy.valueName = "G";
  anisotropy.keyword = "anisotropy";
  anisotropy.type = OptionType::Number;
  anisotropy.group = OptionGroup::SurfaceMetric;
  anisotropy.commands = kSurfaceDistanceCommand;
  anisotropy.range.min = 1.0;
  anisotropy.help = "G >= 1 for the curvature and field metrics (required for them).";
  table.push_back(anisotropy);
  return table;
}

const OptionDeclaration& option(const std::string& flag) {
  const OptionDeclaration* found = findOption(meshOptionDeclarations(), flag);
  if (!found) throw std::logic_error("no mesh option " + flag);
  return *found;
}

}  // namespace

const std::vector<OptionDeclaration>& meshOptionDeclarations() {
  static const std::vector<OptionDeclaration> table = declarations();
  return table;
}

void checkSurfaceMetricChoice(const std::string& metric, bool anisotropyGiven, OptionNaming naming) {
  const std::string kind = metric.substr(0, metric.find(':'));
  const bool needsAnisotropy = kind == "curvature" || kind == "field";
  const OptionDeclaration& anisotropy = option("--anisotropy");
  if (needsAnisotropy && !anisotropyGiven)
    throw OptionError(optionWithValue(option("--metric"), metric, naming) + " needs " +
                      optionWithValue(anisotropy, anisotropy.valueName, naming));
  if (!needsAnisotropy && anisotropyGiven)
    throw OptionError(optionName(anisotropy, naming) + " applies to the curvature and field metrics only");
}

}  // namespace stvd
