#include "stvd/imaging/seed_options.hpp"

namespace stvd::imaging {
namespace {

OptionDeclaration triple(const std::string& flag, const std::string& keyword, OptionType type, OptionGroup group,
                         OptionCommands commands, const std::string& help) {
  OptionDeclaration o;
  o.flag = flag;
  o.valueName = type == OptionType::Voxel ? "I,J,K" : "X,Y,Z";
  o.keyword = keyword;
  o.type = type;
  o.group = group;
  o.commands = commands;
  o.repeatable = true;
  o.help = help;
  return o;
}

std::vector<OptionDeclaration> declarations() {
  const OptionCommands seeded = kDistanceCommand | kPathCommand;
  std::vector<OptionDeclaration> table;
  table.push_back(triple("--seed-voxel", "seeds", OptionType::Voxel, OptionGroup::Seeds, seeded,
                         "0-based voxel index (repeatable)."));

  OptionDeclaration point = triple("--seed-point", "seed_points", OptionType::Point, OptionGroup::Seeds,
                                   seeded | kMeshCommands,
                                   "physical point in RAS millimetres, the NIfTI/scanner convention (repeatable); "
                                   "the nearest voxel is the seed.");
  point.keywordCommands = seeded;
  point.helpFor = {{kSurfaceDistanceCommand,
                    "a point in mesh coordinates (repeatable): the nearest vertex, or with --seed-at point the "
                    "closest point of the surface itself."},
                   {kTetMeshDistanceCommand,
                    "a point in mesh coordinates (repeatable): it must lie in a tetrahedron, and the nearest vertex "
                    "is the seed."}};
  table.push_back(point);

  OptionDeclaration lps;
  lps.flag = "--lps";
  lps.keyword = "lps";
  lps.keywordCommands = seeded;
  lps.type = OptionType::Switch;
  lps.group = OptionGroup::Seeds;
  lps.commands = seeded | kTetMeshDistanceCommand;
  lps.help = "read --seed-point coordinates as LPS (ITK, DICOM, Slicer) instead.";
  lps.helpFor = {{kPathCommand, "read --seed-point and --target-point as LPS (ITK, DICOM, Slicer) instead of RAS."},
                 {kTetMeshDistanceCommand,
                  "with a tensor image: the mesh (and --seed-point) is in LPS coordinates; by default it is in RAS, "
                  "the NIfTI/scanner convention."}};
  table.push_back(lps);

  OptionDeclaration labels;
  labels.flag = "--seeds";
  labels.valueName = "LABELS";
  labels.keyword = "seed_labels";
  labels.type = OptionType::Text;
  labels.group = OptionGroup::Seeds;
  labels.commands = seeded | kSurfaceDistanceCommand;
  labels.keywordCommands = seeded;
  labels.help =
      "every non-zero voxel of the image LABELS (same grid) inside the domain is a seed; the others are left out "
      "(counted in the report), and none inside is an error.";
  labels.helpFor = {
      {kSurfaceDistanceCommand,
       "seed vertices from a file of the surface's vertices: a FreeSurfer .label (its vertices), an annotation "
       "(.annot) or GIfTI label file (.label.gii) with --seed-region (the regions' vertices), or per-vertex values "
       "(.func.gii, .shape.gii, curv, .mgh, .mgz: every non-zero vertex)."}};
  table.push_back(labels);

  table.push_back(triple("--target-voxel", "targets", OptionType::Voxel, OptionGroup::Targets, kPathCommand,
                         "0-based voxel index (repeatable)."));
  table.push_back(triple("--target-point", "target_points", OptionType::Point, OptionGroup::Targets, kPathCommand,
                         "physical point in RAS millimetres (repeatable); the nearest voxel is the target."));
  OptionDeclaration targets;
  targets.flag = "--targets";
  targets.valueName = "LABELS";
  targets.keyword = "target_labels";
  targets.type = OptionType::Text;
  targets.group = OptionGroup::Targets;
  targets.commands = kPathCommand;
  targets.help =
      "one path per distinct non-zero label value of LABELS (same grid), ending at that region's voxel nearest "
      "to the seeds (geodesically).";
  table.push_back(targets);
  return table;
}

}  // namespace

const std::vector<OptionDeclaration>& seedOptionDeclarations() {
  static const std::vector<OptionDeclaration> table = declarations();
  return table;
}

namespace {

/// "--seed-voxel I,J,K" or "seeds=".
std::string toGive(const std::string& flag, OptionNaming naming) {
  const OptionDeclaration& o = *findOption(seedOptionDeclarations(), flag);
  return naming == OptionNaming::Keywords ? o.keyword + "=" : o.flag + " " + o.valueName;
}

std::string oneOf(const std::string& what, const char* voxel, const char* point, const char* labels,
                  OptionNaming naming) {
  return "no " + what + ": add " + toGive(voxel, naming) + ", " + toGive(point, naming) + " or " +
         toGive(labels, naming);
}

}  // namespace

std::string noSeedMessage(OptionNaming naming) {
  return oneOf("seed", "--seed-voxel", "--seed-point", "--seeds", naming);
}

std::string noTargetMessage(OptionNaming naming) {
  return oneOf("target", "--target-voxel", "--target-point", "--targets", naming);
}

std::vector<std::array<int, 3>> voxelsOf(const OptionValues& values, const std::string& flag) {
  std::vector<std::array<int, 3>> voxels;
  for (const OptionValue& v : values.all(flag)) {
    const auto& p = std::get<std::array<double, 3>>(v);
    voxels.push_back({static_cast<int>(p[0]), static_cast<int>(p[1]), static_cast<int>(p[2])});
  }
  return voxels;
}

std::vector<std::array<double, 3>> pointsOf(const OptionValues& values, const std::string& flag) {
  std::vector<std::array<double, 3>> points;
  for (const OptionValue& v : values.all(flag)) points.push_back(std::get<std::array<double, 3>>(v));
  return points;
}

}  // namespace stvd::imaging
