#include "geodesic_options.hpp"

#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/itk/image_grid.hpp"
#include "stvd/imaging/seed_options.hpp"

namespace stvd::tool {

SeedOptions seedOptionsOf(const OptionValues& values) {
  SeedOptions o;
  o.seedVoxels = imaging::voxelsOf(values, "--seed-voxel");
  o.seedPoints = imaging::pointsOf(values, "--seed-point");
  o.seedPointsInLps = values.has("--lps");
  o.seedLabels = values.text("--seeds").value_or("");
  return o;
}

std::vector<Seed> resolveSeeds(const std::string& inputPath, const SeedOptions& o, const TensorInput& input,
                               const imaging::MetricOptions& metric, const std::vector<std::uint8_t>& inDomain,
                               std::size_t& labelSeedsLeftOut, const std::string& role) {
  std::vector<Seed> seeds = imaging::seedVoxelsAt(inputPath, o.seedVoxels, o.seedPoints, o.seedPointsInLps, input,
                                                  metric, inDomain, role);
  if (!o.seedLabels.empty()) {
    const imaging::ScalarImage labels = imaging::readScalarImageOnGrid(o.seedLabels, input.read.volume.geometry,
                                                                       "the seed labels are", inputPath);
    noteInputWarnings(o.seedLabels, labels.warnings);
    const std::vector<Seed> labelled = imaging::labelSeedVoxels(o.seedLabels, labels, inputPath,
                                                                input.read.volume.geometry, inDomain, labelSeedsLeftOut);
    seeds.insert(seeds.end(), labelled.begin(), labelled.end());
  }
  return seeds;
}

}  // namespace stvd::tool
