#include "stvd/imaging/tensor_input_options.hpp"

#include <stdexcept>

#include "stvd/imaging/tensor_input.hpp"
#include "stvd/imaging/tensor_plausibility.hpp"

namespace stvd::imaging {
namespace {

std::vector<OptionDeclaration> declarations() {
  const TensorInputOptions defaults;
  std::vector<OptionDeclaration> table;
  const OptionCommands readers = kVolumeCommands | kTetMeshDistanceCommand;

  OptionDeclaration order;
  order.flag = "--tensor-order";
  order.valueName = "ORDER";
  order.keyword = "tensor_order";
  order.keywordCommands = kVolumeCommands | kMeshCommands;  // also rows of tensors on surfaces
  order.type = OptionType::Choice;
  order.group = OptionGroup::TensorFile;
  order.commands = readers | kInfoCommand;
  for (const TensorOrder o : {TensorOrder::Lower, TensorOrder::Fsl, TensorOrder::Mrtrix})
    order.choices.push_back({tensorOrderName(o), tensorOrderComponents(o)});
  order.choices[0].help += " (NIfTI standard, DIPY, ANTs; alias nifti)";
  order.choices[1].help += " (FSL dtifit; alias upper)";
  order.choices[2].help += " (MRtrix)";
  order.aliases = {{"nifti", tensorOrderName(TensorOrder::Lower)}, {"upper", tensorOrderName(TensorOrder::Fsl)}};
  order.choiceLayout = ChoiceLayout::Lines;
  order.help = "component order of a six-volume NIfTI file (no default):\n{choices}.";
  order.helpFor = {{kTetMeshDistanceCommand,
                    "component order of the attributes:\n{choices};\nfor an image, as for grids. Attribute tensors "
                    "are in mesh coordinates."}};
  order.defaults = {std::monostate{}, std::monostate{}, tensorOrderName(kDefaultAttributeTensorOrder)};
  table.push_back(order);

  OptionDeclaration frame;
  frame.flag = "--tensor-frame";
  frame.valueName = "FRAME";
  frame.keyword = "tensor_frame";
  frame.keywordCommands = kVolumeCommands;
  frame.type = OptionType::Choice;
  frame.group = OptionGroup::TensorFile;
  frame.commands = readers | kInfoCommand;
  frame.choices = {{tensorFrameName(TensorFrame::Voxel), "along the image index axes i,j,k (DIPY, FSL fits)"},
                   {tensorFrameName(TensorFrame::World),
                    "NIfTI: RAS scanner axes (MRtrix), NRRD: the measurement frame, in the NRRD space"}};
  frame.choiceLayout = ChoiceLayout::Lines;
  frame.help =
      "frame of the six numbers:\n{choices}.\nWhen not stated: voxel for NIfTI in the lower and fsl orders, world "
      "for NIfTI in the mrtrix order and for NRRD.";
  table.push_back(frame);

  OptionDeclaration mask;
  mask.flag = "--mask";
  mask.valueName = "FILE";
  mask.keyword = "mask";
  mask.keywordCommands = kVolumeCommands;
  mask.type = OptionType::Text;
  mask.group = OptionGroup::TensorFile;
  mask.commands = readers | kInfoCommand | kSurfaceDistanceCommand;
  mask.help = "only voxels where FILE is non-zero (same grid as the tensors).";
  mask.helpFor = {{kSurfaceDistanceCommand,
                   "only the faces whose corners are all non-zero in FILE, one value per vertex (.func.gii, "
                   ".shape.gii, .label.gii, curv, .mgh, .mgz, a FreeSurfer .label: its vertices): paths stay on "
                   "them; other vertices are unreached."}};
  table.push_back(mask);

  OptionDeclaration kind;
  kind.flag = "--tensor-kind";
  kind.valueName = "KIND";
  kind.keyword = "tensor_kind";
  kind.keywordCommands = kVolumeCommands | kTetMeshDistanceCommand | kCohortCommand;
  kind.type = OptionType::Choice;
  kind.group = OptionGroup::Metric;
  kind.commands = readers | kCohortCommand;
  kind.choices = {{tensorKindName(TensorKind::Diffusion), "the file holds diffusion tensors D"},
                  {tensorKindName(TensorKind::Metric),
                   "the file holds the metric G (cost of a step v is sqrt(v^T G v), v in mm)"}};
  kind.choiceLayout = ChoiceLayout::Lines;
  kind.help = "{choices}.";
  const std::string kindName = tensorKindName(defaults.metric.kind);
  kind.defaults = {kindName, kindName, kindName};
  table.push_back(kind);

  OptionDeclaration diffusion;
  diffusion.flag = "--diffusion-metric";
  diffusion.valueName = "M";
  diffusion.keyword = "diffusion_metric";
  diffusion.keywordCommands = kind.keywordCommands;
  diffusion.type = OptionType::Choice;
  diffusion.group = OptionGroup::Metric;
  diffusion.commands = kind.commands;
  diffusion.choices = {
      {diffusionMetricName(DiffusionMetric::NormalizedInverse),
       "G = (D/MD)^-1, MD = trace(D)/3, so isotropic tissue costs 1 per mm (O'Donnell et al. 2002)"},
      {diffusionMetricName(DiffusionMetric::NormalizedAdjugate),
       "G = adj(D/MD), anisotropic tissue cheaper still (Fuster et al. 2016)"}};
  diffusion.choiceLayout = ChoiceLayout::Lines;
  diffusion.help = "{choices}.";
  const std::string metricName = diffusionMetricName(defaults.metric.diffusionMetric);
  diffusion.defaults = {metricName, metricName, metricName};
  table.push_back(diffusion);

  OptionDeclaration cap;
  cap.flag = "--max-anisotropy";
  cap.valueName = "A";
  cap.keyword = "max_anisotropy";
  cap.keywordCommands = kind.keywordCommands;
  cap.type = OptionType::Number;
  cap.group = OptionGroup::Metric;
  cap.commands = kind.commands | kInfoCommand;
  cap.range.min = 1.0;
  cap.help =
      "raise eigenvalues below lambda_max/A to it, which also repairs zero and negative eigenvalues (default "
      "{default} for diffusion tensors; a metric is taken as given, with only zero and negative eigenvalues "
      "raised to lambda_max/{default}).";
  cap.helpFor = {{kInfoCommand, "count tensors with lambda_max/lambda_min above A (default {default})."}};
  // Unset in TensorInputOptions: the cap depends on the tensor kind.
  cap.defaults = {kDefaultMaxAnisotropy, kDefaultMaxAnisotropy, kDefaultMaxAnisotropy};
  table.push_back(cap);

  OptionDeclaration fa;
  fa.flag = "--fa-threshold";
  fa.valueName = "T";
  fa.keyword = "fa_threshold";
  fa.keywordCommands = kind.keywordCommands;
  fa.type = OptionType::Number;
  fa.group = OptionGroup::Metric;
  fa.commands = kind.commands;
  fa.range = {0.0, 1.0, /*minExcluded=*/false, /*maxExcluded=*/true};
  fa.help = "only voxels whose tensor has FA >= T (diffusion tensors).";
  table.push_back(fa);

  OptionDeclaration accept;
  accept.flag = "--accept-implausible-tensors";
  accept.keyword = "accept_implausible_tensors";
  accept.keywordCommands = kVolumeCommands;
  accept.type = OptionType::Switch;
  accept.group = OptionGroup::Metric;
  accept.commands = readers;
  accept.help = "go on although more than " + std::to_string(static_cast<int>(100 * kMaxNotPositiveDefiniteShare + 0.5)) +
                " % of the tensors are not positive definite, which a wrong --tensor-order gives (otherwise exit "
                "3; stvd info tries each order).";
  table.push_back(accept);

  OptionDeclaration misaligned;
  misaligned.flag = "--accept-misaligned-tensors";
  misaligned.keyword = "accept_misaligned_tensors";
  misaligned.keywordCommands = kVolumeCommands;
  misaligned.type = OptionType::Switch;
  misaligned.group = OptionGroup::Metric;
  misaligned.commands = readers;
  misaligned.help =
      "go on although the tensors' principal directions follow the tracts clearly better with their components "
      "flipped or permuted along the image axes, which an image reoriented without rotating its tensors gives "
      "(otherwise exit 3; stvd info shows every frame).";
  table.push_back(misaligned);
  return table;
}

}  // namespace

const std::vector<OptionDeclaration>& tensorInputOptionDeclarations() {
  static const std::vector<OptionDeclaration> table = declarations();
  return table;
}

const OptionDeclaration& tensorInputOption(const std::string& flag) {
  const OptionDeclaration* option = findOption(tensorInputOptionDeclarations(), flag);
  if (!option) throw std::logic_error("no tensor input option " + flag);
  return *option;
}

TensorInputOptions tensorInputOptionsOf(const OptionValues& values) {
  TensorInputOptions options;
  options.naming = values.naming();
  if (const auto order = values.text("--tensor-order")) options.order = parseTensorOrder(*order);
  if (const auto frame = values.text("--tensor-frame")) options.frame = parseTensorFrame(*frame);
  if (const auto mask = values.text("--mask")) options.maskPath = *mask;
  if (const auto kind = values.text("--tensor-kind")) options.metric.kind = *parseTensorKind(*kind);
  if (const auto metric = values.text("--diffusion-metric"))
    options.metric.diffusionMetric = *parseDiffusionMetric(*metric);
  if (const auto cap = values.number("--max-anisotropy")) options.metric.maxAnisotropy = *cap;
  if (const auto threshold = values.number("--fa-threshold")) options.metric.faThreshold = *threshold;
  if (values.has("--accept-implausible-tensors")) options.acceptImplausible = true;
  if (values.has("--accept-misaligned-tensors")) options.acceptMisaligned = true;
  // The combinations are checked where the options are assembled, so that
  // no front end (command or keyword call) can leave them out.
  checkTensorInputOptions(options);
  return options;
}

}  // namespace stvd::imaging
