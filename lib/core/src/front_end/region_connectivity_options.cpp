#include "stvd/front_end/region_connectivity_options.hpp"

namespace stvd {
namespace {

std::vector<OptionDeclaration> declarations() {
  std::vector<OptionDeclaration> table;

  OptionDeclaration labels;
  labels.flag = "--labels";
  labels.valueName = "LABELS";
  labels.keyword = "labels";
  labels.type = OptionType::Text;
  labels.group = OptionGroup::Regions;
  labels.commands = kConnectivityCommand;
  labels.help = "the region image (required): each distinct non-zero integer value is a region.";
  table.push_back(labels);

  OptionDeclaration threads;
  threads.flag = "--threads";
  threads.valueName = "N";
  threads.keyword = "threads";
  threads.type = OptionType::Integer;
  threads.group = OptionGroup::Regions;
  threads.commands = kConnectivityCommand | kSurfaceDistanceCommand | kDistanceCommand | kPathCommand;
  threads.keywordCommands = kConnectivityCommand;
  threads.range = {1.0, 1024.0};
  // threadCountFor(0, ...): one thread per core.
  threads.defaultText = "the number of cores";
  threads.help =
      "regions propagated in parallel, and with --fod-basis the voxels of the FOD metric's table (default: "
      "{default}); the table does not depend on N.";
  threads.helpFor = {{kSurfaceDistanceCommand,
                      "with --region-matrix or --nearest-region: regions propagated in parallel (default: "
                      "{default}); the results do not depend on N."},
                     {kDistanceCommand,
                      "with --fod-basis: voxels of the FOD metric's table computed in parallel (default: {default}); "
                      "the distances do not depend on N."},
                     {kPathCommand,
                      "with --fod-basis: voxels of the FOD metric's table computed in parallel (default: {default}); "
                      "the paths do not depend on N."}};
  table.push_back(threads);
  return table;
}

}  // namespace

const std::vector<OptionDeclaration>& regionConnectivityOptionDeclarations() {
  static const std::vector<OptionDeclaration> table = declarations();
  return table;
}

unsigned regionThreadsOf(const OptionValues& values) {
  return static_cast<unsigned>(values.integer("--threads").value_or(0));
}

}  // namespace stvd
