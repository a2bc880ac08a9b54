#include "stvd/imaging/seed_voxels.hpp"

#include <algorithm>
#include <cmath>

#include "stvd/errors.hpp"
#include "stvd/front_end/number_text.hpp"
#include "stvd/imaging/symmetric_eigen.hpp"
#include "stvd/voxel_grid/label_regions.hpp"

namespace stvd::imaging {

using text::fixed;
using text::withThousands;

std::string voxelText(const VoxelIndex& v) {
  return "(" + std::to_string(v.i) + ", " + std::to_string(v.j) + ", " + std::to_string(v.k) + ")";
}

std::string pointText(const Vec3d& p, int decimals) {
  return "(" + fixed(p.x, decimals) + ", " + fixed(p.y, decimals) + ", " + fixed(p.z, decimals) + ")";
}

Vec3d lpsToRas(const Vec3d& p) { return {-p.x, -p.y, p.z}; }

std::string whyOutsideDomain(std::size_t v, const TensorInput& input, const MetricOptions& metric) {
  if (!input.mask.empty() && input.mask[v] == 0) return "it is outside the mask (" + input.maskDescription + ")";
  if (v >= input.read.volume.tensors.size()) return "it is outside the domain";  // an FOD input has no tensors
  const SymTensor3& t = input.read.volume.tensors[v];
  const float c[6] = {t.xx, t.xy, t.xz, t.yy, t.yz, t.zz};
  bool zero = true;
  for (float x : c) {
    if (!std::isfinite(x)) return "its tensor is not finite";
    zero = zero && x == 0.f;
  }
  if (zero) return "its tensor is zero (no data there)";
  const SymmetricEigen e = eigenDecompose(t);
  if (!(e.values[0] > 0.0)) return "its tensor has no positive eigenvalue";
  // In words both front ends share (the tool's flag and the package's
  // keyword name the same threshold).
  if (metric.faThreshold)
    return "its FA " + fixed(fractionalAnisotropy(e.values), 3) + " is below the FA threshold " +
           fixed(*metric.faThreshold, 3);
  return "it is outside the domain";
}

std::vector<SeedVoxel> seedVoxelsAt(const std::string& inputName, const std::vector<std::array<int, 3>>& voxels,
                                    const std::vector<std::array<double, 3>>& points, bool pointsInLps,
                                    const TensorInput& input, const MetricOptions& metric,
                                    const std::vector<std::uint8_t>& inDomain, const std::string& role) {
  const GridGeometry& g = input.read.volume.geometry;
  std::vector<SeedVoxel> seeds;
  const std::string size = std::to_string(g.size[0]) + " x " + std::to_string(g.size[1]) + " x " +
                           std::to_string(g.size[2]) + " voxels";
  auto inside = [&](const std::array<long, 3>& idx) {
    for (int a = 0; a < 3; ++a)
      if (idx[a] < 0 || idx[a] >= static_cast<long>(g.size[a])) return false;
    return true;
  };
  auto linear = [&](const VoxelIndex& v) {
    return static_cast<std::size_t>(v.i) + g.size[0] * (static_cast<std::size_t>(v.j) + g.size[1] * v.k);
  };
  auto requireInDomain = [&](const SeedVoxel& s) {
    const std::size_t v = linear(s.index);
    if (!inDomain[v])
      throw NothingToCompute(inputName + ": " + role + " " + s.givenAs +
                             " lies outside the domain: " + whyOutsideDomain(v, input, metric));
  };
  for (const auto& s : voxels) {
    SeedVoxel seed{{s[0], s[1], s[2]}, "voxel " + voxelText({s[0], s[1], s[2]})};
    if (!inside({s[0], s[1], s[2]}))
      throw NothingToCompute(inputName + ": " + role + " " + seed.givenAs + " lies outside the image (" + size +
                             ", indices from 0)");
    requireInDomain(seed);
    seeds.push_back(seed);
  }
  for (const auto& p : points) {
    const Vec3d given{p[0], p[1], p[2]};
    const Vec3d lps = pointsInLps ? given : lpsToRas(given);  // the flip is its own inverse
    const Vec3d c = g.physicalPointToIndex(lps);
    const std::array<long, 3> idx{std::lround(c.x), std::lround(c.y), std::lround(c.z)};
    SeedVoxel seed{{static_cast<int>(idx[0]), static_cast<int>(idx[1]), static_cast<int>(idx[2])},
                   std::string("point ") + (pointsInLps ? "LPS " : "RAS ") + pointText(given, 2) + " mm"};
    if (!inside(idx))
      throw NothingToCompute(inputName + ": " + role + " " + seed.givenAs +
                             " lies outside the image (continuous index " + pointText(c, 2) + ", image " + size +
                             ")");
    seed.givenAs += " (voxel " + voxelText(seed.index) + ")";
    requireInDomain(seed);
    seeds.push_back(seed);
  }
  return seeds;
}

std::vector<SeedVoxel> labelSeedVoxels(const std::string& labelsName, const ScalarImage& labels,
                                       const std::string& inputName, const GridGeometry& g,
                                       const std::vector<std::uint8_t>& inDomain, std::size_t& leftOut) {
  requireSameGrid(labels.geometry, g, labelsName, "the seed labels are", inputName);
  std::vector<SeedVoxel> seeds;
  std::size_t nonZero = 0;
  for (std::size_t v = 0; v < labels.values.size(); ++v) {
    if (labels.values[v] == 0.f || std::isnan(labels.values[v])) continue;
    ++nonZero;
    if (!inDomain[v]) {
      ++leftOut;
      continue;
    }
    const std::size_t i = v % g.size[0], j = (v / g.size[0]) % g.size[1], k = v / (g.size[0] * g.size[1]);
    seeds.push_back({{static_cast<int>(i), static_cast<int>(j), static_cast<int>(k)}, "label voxel"});
  }
  if (nonZero == 0) throw NothingToCompute(labelsName + ": the seed label image has no non-zero voxel");
  if (leftOut == nonZero)
    throw NothingToCompute(labelsName + ": none of its " + withThousands(nonZero) +
                           " non-zero voxels lies inside the domain of " + inputName);
  return seeds;
}

std::vector<PathTarget> labelTargets(const std::string& labelsName, const LabelImage& labels,
                                     const std::string& inputName, const GridGeometry& geometry,
                                     const std::vector<std::uint8_t>& inDomain, const std::vector<double>& distance) {
  requireSameGrid(labels.geometry, geometry, labelsName, "the target labels are", inputName);
  const std::vector<LabelRegion> regions = labelRegions(labels.labels, inDomain);
  if (regions.empty()) throw NothingToCompute(labelsName + ": the target label image has no non-zero voxel");
  std::vector<PathTarget> targets;
  for (const LabelRegion& region : regions) {
    const VertexId vertex = nearestReached(distance, region.voxels);
    if (vertex == kNoVertex)
      throw NothingToCompute(labelsName + ": no voxel of label " + std::to_string(region.label) +
                             " lies in the domain of " + inputName + " and is reachable from the seeds");
    targets.push_back({vertex, "label " + std::to_string(region.label)});
  }
  return targets;
}

void requireReachable(const std::string& inputName, const std::vector<PathTarget>& targets,
                      const std::vector<double>& distance) {
  for (const PathTarget& t : targets)
    if (!std::isfinite(distance[t.vertex]))
      throw NothingToCompute(inputName + ": target " + t.name +
                             " is not reachable from the seeds (no path inside the domain connects them)");
}

std::vector<VertexId> sourceVertices(const VoxelGridDomain& domain, const std::vector<SeedVoxel>& seeds) {
  std::vector<VertexId> sources;
  sources.reserve(seeds.size());
  for (const SeedVoxel& s : seeds) sources.push_back(domain.vertexAt(s.index.i, s.index.j, s.index.k));
  std::sort(sources.begin(), sources.end());
  sources.erase(std::unique(sources.begin(), sources.end()), sources.end());
  return sources;
}

}  // namespace stvd::imaging
