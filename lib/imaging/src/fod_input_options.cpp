#include "stvd/imaging/fod_input_options.hpp"

#include <string>

#include "stvd/errors.hpp"
#include "stvd/imaging/spherical_harmonics.hpp"

namespace stvd::imaging {
namespace {

std::vector<OptionDeclaration> declarations() {
  const FodCostOptions defaults;
  std::vector<OptionDeclaration> table;

  OptionDeclaration basis;
  basis.flag = "--fod-basis";
  basis.valueName = "BASIS";
  basis.type = OptionType::Choice;
  basis.group = OptionGroup::FodFile;
  basis.commands = kVolumeCommands;
  basis.keyword = "fod_basis";
  basis.keywordCommands = kFodDistanceCommand;
  // "mrtrix3" is a choice of its own, not an alias: it names the frame too
  // (scanner), where tournier07 in a NIfTI file is DIPY's (voxel frame).
  basis.choices = {
      {"mrtrix3", "MRtrix3's basis (tournier07) in the scanner frame: dwi2fod's output, also as NIfTI"},
      {shBasisName(ShBasis::Tournier07), "DIPY tournier07, legacy=False (= MRtrix3's functions)"},
      {shBasisName(ShBasis::Tournier07Legacy), "DIPY tournier07, legacy=True (MRtrix 0.2)"},
      {shBasisName(ShBasis::Descoteaux07), "DIPY descoteaux07, legacy=False"},
      {shBasisName(ShBasis::Descoteaux07Legacy), "DIPY descoteaux07, legacy=True (DIPY 1.6's CSD default)"}};
  basis.choiceLayout = ChoiceLayout::Lines;
  basis.help =
      "the input is an FOD image (spherical-harmonic coefficients, X Y Z N with N = 15, 28, 45, 66 or 91: lmax "
      "4 to 12) in this basis:\n{choices}.\nThe cost is F* of docs/fod.md, tabulated per voxel (on --threads): "
      "along the lattice of order 2 for STVD (the default of stvd distance) and Lanthier, along the 26 neighbour "
      "directions for Dijkstra (the method of stvd path and stvd connectivity).";
  table.push_back(basis);

  OptionDeclaration frame;
  frame.flag = "--fod-frame";
  frame.valueName = "FRAME";
  frame.type = OptionType::Choice;
  frame.group = OptionGroup::FodFile;
  frame.commands = kVolumeCommands;
  frame.keyword = "fod_frame";
  frame.keywordCommands = kFodDistanceCommand;
  frame.choices = {{fodFrameName(FodFrame::Scanner), "the scanner's RAS axes (MRtrix3)"},
                   {fodFrameName(FodFrame::Voxel), "the image's index axes as stored (DIPY)"}};
  frame.choiceLayout = ChoiceLayout::Lines;
  frame.help =
      "axes of the coefficients' angles:\n{choices}.\nWhen not stated: scanner for .mif and for mrtrix3, voxel for "
      "DIPY's basis names in NIfTI.";
  table.push_back(frame);

  OptionDeclaration floor;
  floor.flag = "--fod-floor";
  floor.valueName = "F";
  floor.type = OptionType::Number;
  floor.group = OptionGroup::FodFile;
  floor.commands = kVolumeCommands;
  floor.keyword = "fod_floor";
  floor.keywordCommands = kFodDistanceCommand;
  floor.range = {0.0, 1.0, /*minExcluded=*/true, /*maxExcluded=*/false};
  floor.help =
      "smallest normalised FOD amplitude counted: no direction costs more than F^-P per mm, the voxel's best one "
      "costs 1 (default {default}).";
  floor.defaults = {defaults.floor, defaults.floor, defaults.floor};
  table.push_back(floor);

  OptionDeclaration power;
  power.flag = "--fod-power";
  power.valueName = "P";
  power.type = OptionType::Number;
  power.group = OptionGroup::FodFile;
  power.commands = kVolumeCommands;
  power.keyword = "fod_power";
  power.keywordCommands = kFodDistanceCommand;
  power.range = {0.0, 8.0, /*minExcluded=*/true, /*maxExcluded=*/false};
  power.help = "exponent P of the normalised amplitude: above 1 sharpens the lobes (default {default}).";
  power.defaults = {defaults.power, defaults.power, defaults.power};
  table.push_back(power);
  return table;
}

}  // namespace

const std::vector<OptionDeclaration>& fodInputOptionDeclarations() {
  static const std::vector<OptionDeclaration> table = declarations();
  return table;
}

FodInputOptions fodInputOptionsOf(const OptionValues& values) {
  FodInputOptions options;
  if (const auto basis = values.text("--fod-basis")) options.read.basis = *basis;
  if (const auto frame = values.text("--fod-frame")) options.read.frame = parseFodFrame(*frame);
  if (const auto floor = values.number("--fod-floor")) options.cost.floor = *floor;
  if (const auto power = values.number("--fod-power")) options.cost.power = *power;
  if (!options.given())
    for (const char* flag : {"--fod-frame", "--fod-floor", "--fod-power"})
      if (values.has(flag)) throw OptionError(std::string(flag) + " applies to FOD images: add --fod-basis BASIS");
  return options;
}

}  // namespace stvd::imaging
