#include "stvd/tetmesh/tet_mesh_options.hpp"

namespace stvd::tetmesh {
namespace {

std::vector<OptionDeclaration> declarations() {
  std::vector<OptionDeclaration> table;

  OptionDeclaration tensors;
  tensors.flag = "--tensors";
  tensors.valueName = "SOURCE";
  tensors.keyword = "tensors";
  tensors.type = OptionType::Text;
  tensors.group = OptionGroup::MeshMetric;
  tensors.commands = kTetMeshDistanceCommand;
  tensors.help =
      "node: six .node point attributes per vertex; ele: six .ele attributes per tetrahedron, averaged at each "
      "vertex weighted by the volumes of its tetrahedra; or a tensor image (.nii, .nii.gz, .nrrd, .nhdr, .mif, "
      ".mif.gz) whose metric is sampled at the vertices by log-Euclidean trilinear interpolation. None: the "
      "Euclidean metric.";
  table.push_back(tensors);

  OptionDeclaration attribute;
  attribute.flag = "--tensor-attribute";
  attribute.valueName = "A";
  attribute.type = OptionType::Integer;
  attribute.group = OptionGroup::MeshMetric;
  attribute.commands = kTetMeshDistanceCommand;
  attribute.range.min = 0.0;
  attribute.help = "0-based index of the first of the six attributes (default {default}).";
  const long long first = kDefaultFirstTensorAttribute;
  attribute.defaults = {first, first, first};
  table.push_back(attribute);

  OptionDeclaration outside;
  outside.flag = "--outside-image";
  outside.valueName = "P";
  outside.type = OptionType::Choice;
  outside.group = OptionGroup::MeshMetric;
  outside.commands = kTetMeshDistanceCommand;
  outside.choices = {{"error", "exit 3"}, {"mask", "left out of the domain"}};
  outside.help = "with a tensor image, for vertices beyond the image's extent: {choices}.";
  outside.defaults = {std::monostate{}, std::monostate{}, std::string("error")};
  table.push_back(outside);

  OptionDeclaration reference;
  reference.flag = "--reference";
  reference.valueName = "IMAGE";
  reference.type = OptionType::Text;
  reference.group = OptionGroup::Output;
  reference.commands = kTetMeshDistanceCommand;
  reference.help =
      "scalar image (e.g. an FA map or a label image) whose grid an image output takes; the mesh is RAS unless "
      "--lps.";
  table.push_back(reference);
  return table;
}

}  // namespace

const std::vector<OptionDeclaration>& tetMeshOptionDeclarations() {
  static const std::vector<OptionDeclaration> table = declarations();
  return table;
}

}  // namespace stvd::tetmesh
