#include "geodesic_options.hpp"

#include <cmath>

#include "stvd/itk/image_io_error.hpp"
#include "stvd/itk/scalar_image.hpp"
#include "stvd/itk/symmetric_eigen.hpp"
#include "stvd/stencil.hpp"
#include "stvd/steiner_propagation.hpp"

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
    const std::string m = args.value(a);
    o.lanthier = m == "lanthier";
    if (m == "stvd")
      o.method = Method::ShortTermVectorDijkstra;
    else if (m == "dijkstra")
      o.method = Method::Dijkstra;
    else if (!o.lanthier)
      usageError("--method: '" + m + "' is not one of stvd, dijkstra, lanthier");
  } else if (a == "--steiner") {
    o.steinerPoints = parseInteger(a, args.value(a));
    if (o.steinerPoints < 1 || o.steinerPoints > kMaxSteinerPoints)
      usageError("--steiner must be between 1 and " + std::to_string(kMaxSteinerPoints));
  } else if (a == "--k") {
    o.k = parseInteger(a, args.value(a));
    o.kGiven = true;
    if (o.k < 1 || o.k > kMaxMemoryDepth)
      usageError("--k must be between 1 and " + std::to_string(kMaxMemoryDepth));
  } else if (a == "--chain-measure") {
    const std::string m = args.value(a);
    if (m == "segment")
      o.chainMeasure = ChainMeasure::Segment;
    else if (m == "projection")
      o.chainMeasure = ChainMeasure::ProjectionWeighted;
    else if (m == "largest")
      o.chainMeasure = ChainMeasure::LargestEdgeNorm;
    else
      usageError("--chain-measure: '" + m + "' is not one of segment, projection, largest");
    o.chainMeasureGiven = true;
  } else if (a == "--no-memory-check") {
    args.noValue(a);
    o.memoryCheck = false;
  } else if (a == "--domain-connectivity") {
    const std::string c = args.value(a);
    if (c == "6")
      o.connectivity = VoxelConnectivity::Faces;
    else if (c == "18")
      o.connectivity = VoxelConnectivity::Edges;
    else if (c == "26")
      o.connectivity = VoxelConnectivity::Corners;
    else
      usageError("--domain-connectivity: '" + c + "' is not one of 6, 18, 26");
    o.connectivityGiven = true;
  } else if (a == "--stencil") {
    o.stencil = args.value(a);
    o.stencilGiven = true;
    try {
      Stencil::byName(o.stencil);
    } catch (const std::invalid_argument&) {
      usageError("--stencil: '" + o.stencil + "' is not one of 6, 18, 26, 98, 290");
    }
  } else {
    return false;
  }
  return true;
}

namespace {

/// The rules every command shares: STVD's options are refused where no
/// STVD runs (`stvdOnly`: every method but stvd; otherwise lanthier only),
/// and --steiner goes with lanthier and lanthier needs it.
void checkCommonChoice(const PropagationChoice& o, bool stvdOnly, const std::string& cellEdge,
                       int suggestedSteinerPoints) {
  const bool refuseStvdOptions = stvdOnly ? (o.lanthier || o.method != Method::ShortTermVectorDijkstra) : o.lanthier;
  if (o.kGiven && refuseStvdOptions) usageError("--k applies to --method stvd only");
  if (o.chainMeasureGiven && refuseStvdOptions) usageError("--chain-measure applies to --method stvd only");
  if (o.lanthier && o.steinerPoints == 0)
    usageError("--method lanthier needs --steiner M, the Steiner points per " + cellEdge + " (1.." +
               std::to_string(kMaxSteinerPoints) + "; try " + std::to_string(suggestedSteinerPoints) + ")");
  if (!o.lanthier && o.steinerPoints != 0) usageError("--steiner applies to --method lanthier only");
}

}  // namespace

void checkPropagationChoice(const PropagationChoice& o, bool lanthierAllowed) {
  if (o.lanthier && !lanthierAllowed)
    usageError("--method lanthier gives distances but no predecessors, which paths need; use stvd or dijkstra");
  checkCommonChoice(o, /*stvdOnly=*/true, "cube edge", 2);
  if (o.lanthier && o.stencilGiven) usageError("--stencil does not apply to --method lanthier (it uses cubes)");
  // Every method must reach the same voxels: a stencil has to contain the
  // steps across the contacts that the connectivity joins (the 98 and 290
  // stencils contain all 26 unit steps).
  if (!o.lanthier) {
    const bool edgeSteps = o.stencil != "6", cornerSteps = edgeSteps && o.stencil != "18";
    if (o.connectivity == VoxelConnectivity::Edges && !edgeSteps)
      usageError("--domain-connectivity 18 joins voxels that touch along an edge, which the 6-neighbour stencil "
                 "cannot step between; use --stencil 18 or larger");
    if (o.connectivity == VoxelConnectivity::Corners && !cornerSteps)
      usageError("--domain-connectivity 26 joins voxels that touch at a corner, which the " + o.stencil +
                 "-neighbour stencil cannot step between; use --stencil 26 or larger");
  }
}

void checkMeshPropagationChoice(const PropagationChoice& o, const std::string& cellEdge, int suggestedSteinerPoints) {
  checkCommonChoice(o, /*stvdOnly=*/false, cellEdge, suggestedSteinerPoints);
  if (o.connectivityGiven) usageError("--domain-connectivity applies to voxel grids only");
}

PropagationOptions propagationOptions(const PropagationChoice& o) {
  PropagationOptions options;
  options.method = o.method;
  options.k = o.method == Method::Dijkstra ? 1 : o.k;
  options.chainMeasure = o.chainMeasure;
  return options;
}

std::string methodText(const PropagationChoice& o) {
  if (o.lanthier)
    return "Lanthier Steiner-point propagation with M = " + std::to_string(o.steinerPoints) + " points per cube edge";
  if (o.method == Method::Dijkstra) return "Dijkstra";
  const char* measure = o.chainMeasure == ChainMeasure::Segment            ? " (segment measure)"
                        : o.chainMeasure == ChainMeasure::LargestEdgeNorm ? " (largest-norm chain measure)"
                                                                          : " (projection chain measure)";
  return "STVD with k = " + std::to_string(o.k) + measure;
}

std::string connectivityText(VoxelConnectivity c) {
  switch (c) {
    case VoxelConnectivity::Faces: return "domain connectivity 6 (voxels joined through faces only)";
    case VoxelConnectivity::Edges: return "domain connectivity 18 (voxels also joined across edge contacts)";
    case VoxelConnectivity::Corners: return "domain connectivity 26 (voxels also joined across edge and corner contacts)";
  }
  return "?";
}

std::string voxelText(const VoxelIndex& v) {
  return "(" + std::to_string(v.i) + ", " + std::to_string(v.j) + ", " + std::to_string(v.k) + ")";
}

std::string pointText(const Vec3d& p, int decimals) {
  return "(" + fixed(p.x, decimals) + ", " + fixed(p.y, decimals) + ", " + fixed(p.z, decimals) + ")";
}

Vec3d lpsToRas(const Vec3d& p) { return {-p.x, -p.y, p.z}; }

namespace {

/// Why voxel v is outside the domain, for an error message.
std::string whyOutside(std::size_t v, const TensorInput& input, const imaging::MetricOptions& metric) {
  const SymTensor3& t = input.read.volume.tensors[v];
  if (!input.mask.empty() && input.mask[v] == 0) return "it is outside the mask (" + input.maskDescription + ")";
  const float c[6] = {t.xx, t.xy, t.xz, t.yy, t.yz, t.zz};
  bool zero = true;
  for (float x : c) {
    if (!std::isfinite(x)) return "its tensor is not finite";
    zero = zero && x == 0.f;
  }
  if (zero) return "its tensor is zero (no data there)";
  const imaging::SymmetricEigen e = imaging::eigenDecompose(t);
  if (!(e.values[0] > 0.0)) return "its tensor has no positive eigenvalue";
  if (metric.faThreshold)
    return "its FA " + fixed(imaging::fractionalAnisotropy(e.values), 3) + " is below --fa-threshold";
  return "it is outside the domain";
}

}  // namespace

std::vector<Seed> resolveSeeds(const std::string& inputPath, const SeedOptions& o, const TensorInput& input,
                               const imaging::MetricOptions& metric, const std::vector<std::uint8_t>& inDomain,
                               std::size_t& labelSeedsLeftOut, const std::string& role) {
  const GridGeometry& g = input.read.volume.geometry;
  std::vector<Seed> seeds;
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
  auto requireInDomain = [&](const Seed& s) {
    const std::size_t v = linear(s.index);
    if (!inDomain[v])
      throw ToolError(kExitDomain, inputPath + ": " + role + " " + s.givenAs + " lies outside the domain: " +
                                       whyOutside(v, input, metric));
  };
  for (const auto& s : o.seedVoxels) {
    Seed seed{{s[0], s[1], s[2]}, "voxel " + voxelText({s[0], s[1], s[2]})};
    if (!inside({s[0], s[1], s[2]}))
      throw ToolError(kExitDomain, inputPath + ": " + role + " " + seed.givenAs + " lies outside the image (" + size +
                                       ", indices from 0)");
    requireInDomain(seed);
    seeds.push_back(seed);
  }
  for (const auto& p : o.seedPoints) {
    const Vec3d given{p[0], p[1], p[2]};
    const Vec3d lps = o.seedPointsInLps ? given : lpsToRas(given);  // the flip is its own inverse
    const Vec3d c = g.physicalPointToIndex(lps);
    const std::array<long, 3> idx{std::lround(c.x), std::lround(c.y), std::lround(c.z)};
    Seed seed{{static_cast<int>(idx[0]), static_cast<int>(idx[1]), static_cast<int>(idx[2])},
              std::string("point ") + (o.seedPointsInLps ? "LPS " : "RAS ") + pointText(given, 2) + " mm"};
    if (!inside(idx))
      throw ToolError(kExitDomain, inputPath + ": " + role + " " + seed.givenAs + " lies outside the image (continuous index " +
                                       pointText(c, 2) + ", image " + size + ")");
    seed.givenAs += " (voxel " + voxelText(seed.index) + ")";
    requireInDomain(seed);
    seeds.push_back(seed);
  }
  if (!o.seedLabels.empty()) {
    imaging::ScalarImage labels;
    try {
      labels = imaging::readScalarImage(o.seedLabels);
    } catch (const imaging::ImageIoError& e) {
      throw ToolError(kExitInput, e.what());
    }
    noteInputWarnings(o.seedLabels, labels.warnings);
    const std::string mismatch = imaging::geometryMismatch(labels.geometry, g);
    if (!mismatch.empty())
      throw ToolError(kExitInput, o.seedLabels + ": the seed labels are on another grid than " + inputPath + " (" +
                                      mismatch + ")");
    std::size_t nonZero = 0;
    for (std::size_t v = 0; v < labels.values.size(); ++v) {
      if (labels.values[v] == 0.f || std::isnan(labels.values[v])) continue;
      ++nonZero;
      if (!inDomain[v]) {
        ++labelSeedsLeftOut;
        continue;
      }
      const std::size_t i = v % g.size[0], j = (v / g.size[0]) % g.size[1], k = v / (g.size[0] * g.size[1]);
      seeds.push_back({{static_cast<int>(i), static_cast<int>(j), static_cast<int>(k)}, "label voxel"});
    }
    if (nonZero == 0) throw ToolError(kExitDomain, o.seedLabels + ": the seed label image has no non-zero voxel");
    if (labelSeedsLeftOut == nonZero)
      throw ToolError(kExitDomain, o.seedLabels + ": none of its " + withThousands(nonZero) +
                                       " non-zero voxels lies inside the domain of " + inputPath);
  }
  return seeds;
}

}  // namespace stvd::tool
