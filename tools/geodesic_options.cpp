#include "geodesic_options.hpp"

#include "stvd/itk/image_grid.hpp"
#include "stvd/itk/scalar_image.hpp"

namespace stvd::tool {

bool parseSeedOption(const std::string& a, ArgumentReader& args, SeedOptions& o) {
  if (a == "--seed-voxel") {
    o.seedVoxels.push_back(parseIntegerTriple(a, args.value(a)));
  } else if (a == "--seed-point") {
    o.seedPoints.push_back(parseTriple(a, args.value(a)));
  } else if (a == "--lps") {
    args.noValue(a);
    o.seedPointsInLps = true;
  } else if (a == "--seeds") {
    o.seedLabels = args.value(a);
  } else {
    return false;
  }
  return true;
}

bool parsePropagationOption(const std::string& a, ArgumentReader& args, PropagationChoice& o) {
  if (a == "--method") {
    setMethod(o, args.value(a));
  } else if (a == "--steiner") {
    setSteinerPoints(o, parseInteger(a, args.value(a)));
  } else if (a == "--k") {
    setMemoryDepth(o, parseInteger(a, args.value(a)));
  } else if (a == "--chain-measure") {
    setChainMeasure(o, args.value(a));
  } else if (a == "--no-memory-check") {
    args.noValue(a);
    o.memoryCheck = false;
  } else if (a == "--domain-connectivity") {
    setDomainConnectivity(o, args.value(a));
  } else if (a == "--stencil") {
    setStencil(o, args.value(a));
  } else {
    return false;
  }
  return true;
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
