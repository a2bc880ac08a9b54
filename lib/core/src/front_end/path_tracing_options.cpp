#include "stvd/front_end/path_tracing_options.hpp"

namespace stvd {
namespace {

std::vector<OptionDeclaration> declarations() {
  const PathTracingOptions defaults;
  std::vector<OptionDeclaration> table;

  OptionDeclaration step;
  step.flag = "--step";
  step.valueName = "F";
  step.keyword = "step";
  step.type = OptionType::Number;
  step.group = OptionGroup::Paths;
  step.commands = kPathCommand;
  step.range = {0.0, 1.0, /*minExcluded=*/true, /*maxExcluded=*/false};
  step.help = "integration step as a fraction of the smallest voxel spacing, in (0, 1] (default {default}).";
  step.defaults = {defaults.stepFraction, defaults.stepFraction, defaults.stepFraction};
  table.push_back(step);

  OptionDeclaration smooth;
  smooth.flag = "--smooth";
  smooth.valueName = "N";
  smooth.keyword = "smooth";
  smooth.type = OptionType::Integer;
  smooth.group = OptionGroup::Paths;
  smooth.commands = kPathCommand;
  smooth.range = {0.0, 1000.0};
  smooth.help = "N passes of a [1/4 1/2 1/4] moving average over the interior points (default {default}: none).";
  const long long passes = defaults.smoothingPasses;
  smooth.defaults = {passes, passes, passes};
  table.push_back(smooth);

  OptionDeclaration refine;
  refine.flag = "--no-refine";
  refine.keyword = "refine";
  refine.keywordIsNegation = true;
  refine.type = OptionType::Switch;
  refine.group = OptionGroup::Paths;
  refine.commands = kPathCommand;
  refine.help = "write the traced curves without the refinement.";
  table.push_back(refine);

  OptionDeclaration discrete;
  discrete.flag = "--discrete";
  discrete.keyword = "discrete";
  discrete.type = OptionType::Switch;
  discrete.group = OptionGroup::Paths;
  discrete.commands = kPathCommand;
  discrete.help =
      "write the discrete paths (the predecessor chain: the voxel centres where the measured straight segments of "
      "each path start) instead of the continuous ones.";
  table.push_back(discrete);
  return table;
}

}  // namespace

const std::vector<OptionDeclaration>& pathTracingOptionDeclarations() {
  static const std::vector<OptionDeclaration> table = declarations();
  return table;
}

PathTracingOptions pathTracingOptionsOf(const OptionValues& values) {
  PathTracingOptions options;
  if (const auto step = values.number("--step")) options.stepFraction = *step;
  if (const auto passes = values.integer("--smooth")) options.smoothingPasses = static_cast<int>(*passes);
  if (values.has("--no-refine")) options.refine = false;
  return options;
}

}  // namespace stvd
