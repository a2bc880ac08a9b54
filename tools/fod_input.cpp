#include "fod_input.hpp"

#include <chrono>
#include <ctime>
#include <sstream>

#include "stvd/errors.hpp"
#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/fod_run_description.hpp"
#include "stvd/imaging/spherical_harmonics.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/itk/fod_volume_io.hpp"
#include "stvd/itk/image_grid.hpp"
#include "stvd/system/parallel_tasks.hpp"

namespace stvd::tool {

void checkFodRunOptions(const OptionValues& values, const std::string& stencil) {
  for (const OptionDeclaration& d : imaging::tensorInputOptionDeclarations())
    if (d.flag != "--mask" && values.has(d.flag))
      usageError(d.flag + " applies to tensor images, not to an FOD image (--fod-basis)");
  if (stencil != "6" && stencil != "18" && stencil != "26")
    usageError("--stencil " + stencil +
               ": the FOD metric is tabulated along the 26 neighbour directions; use 6, 18 or 26");
}

FodInput readFodInput(const std::string& path, const imaging::FodInputOptions& options, const std::string& maskPath) {
  FodInput in;
  in.fod = imaging::readFodVolume(path, options.read);
  const imaging::FodField& fod = in.fod;
  // Six coefficients are also a tensor image's six components, and lmax 0
  // has no direction: the tool takes lmax 4 and up (CSD's range).
  if (fod.lmax < 4)
    throw InputError(path + ": " + std::to_string(fod.coefficientCount()) + " volume" + (fod.lmax ? "s" : "") +
                     " (lmax " + std::to_string(fod.lmax) + "): " +
                     (fod.lmax == 2 ? "six volumes are a tensor image's; drop --fod-basis to read tensors"
                                    : "no orientation") +
                     " (FOD images have lmax 4 to 12)");
  const GridGeometry& g = fod.geometry;
  // The seeds', labels' and mask's readers take the grid as a tensor input's.
  in.grid.read.volume.geometry = g;
  if (!maskPath.empty())
    imaging::addMask(in.grid, imaging::readScalarImageOnGrid(maskPath, g, "the mask is", path), maskPath, path);
  noteInputWarnings(in.grid.warnings);
  const std::uint64_t voxels = g.voxelCount();
  in.inDomain = in.grid.mask.empty() ? std::vector<std::uint8_t>(voxels, 1) : in.grid.mask;
  in.counts.total = voxels;
  for (const std::uint8_t inside : in.inDomain) in.counts.domain += inside != 0;
  in.counts.masked = voxels - in.counts.domain;
  if (in.counts.domain == 0) throw NothingToCompute(path + ": the domain is empty: no voxel inside the mask " + maskPath);
  return in;
}

FodTable makeFodTable(const FodInput& input, const imaging::FodCostOptions& cost, unsigned threads,
                      Interrupter* progress, bool segments) {
  FodTable table;
  const auto start = std::chrono::steady_clock::now();
  const std::clock_t cpuStart = std::clock();  // the process's CPU time, all threads
  const GridGeometry& g = input.fod.geometry;
  const imaging::FodCostSampler sampler(input.fod, imaging::defaultFodSampling(g), cost);
  if (segments)
    table.segments = imaging::fodSegmentMetric(sampler, &input.inDomain, threads, progress);
  else
    table.metric = imaging::fodStencilMetric(sampler, &input.inDomain, threads, progress);
  table.cpuSeconds = double(std::clock() - cpuStart) / CLOCKS_PER_SEC;
  table.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  table.directions = sampler.directionCount();
  table.threads =
      threadCountFor(threads, (g.voxelCount() + imaging::kFodMetricBlockVoxels - 1) / imaging::kFodMetricBlockVoxels);
  return table;
}

std::vector<std::string> fodMetricParameters(const FodInput& input, const imaging::FodInputOptions& options,
                                             const FodTable& table) {
  return {"\"metric\": \"fod\"",
          "\"fod_basis\": " + jsonString(imaging::shBasisName(input.fod.basis)),
          "\"fod_basis_given\": " + jsonString(options.read.basis),
          "\"fod_frame\": " + jsonString(imaging::fodFrameName(input.fod.frame)),
          "\"fod_frame_stated\": " + std::string(options.read.frame ? "true" : "false"),
          "\"fod_lmax\": " + std::to_string(input.fod.lmax),
          "\"fod_floor\": " + jsonNumber(options.cost.floor),
          "\"fod_power\": " + jsonNumber(options.cost.power),
          "\"fod_directions\": " + std::to_string(table.directions),
          "\"fod_norm\": " + jsonString(imaging::fodNormDescription(table.segments.has_value()))};
}

std::string fodPrecomputationMember(const FodInput& input, const FodTable& table) {
  return "\"fod_precomputation\": {\"seconds\": " + jsonNumber(table.seconds) +
         ", \"cpu_seconds\": " + jsonNumber(table.cpuSeconds) + ", \"threads\": " + std::to_string(table.threads) +
         ", \"voxels\": " + std::to_string(input.counts.domain) + "}";
}

std::string fodInputText(const std::string& path, const FodInput& input, const imaging::FodInputOptions& options,
                         const FodTable& table) {
  const GridGeometry& g = input.fod.geometry;
  std::ostringstream s;
  s << "Read " << path << " (FOD, lmax " << input.fod.lmax << ", basis " << imaging::shBasisName(input.fod.basis)
    << " in the " << imaging::fodFrameName(input.fod.frame) << " frame): " << g.size[0] << " x " << g.size[1]
    << " x " << g.size[2] << " voxels of " << fixed(g.spacing[0], 2) << " x " << fixed(g.spacing[1], 2) << " x "
    << fixed(g.spacing[2], 2) << " mm, orientation " << orientationCode(g)
    << ". Cost: the convexified FOD norm F* (floor " << jsonNumber(options.cost.floor) << ", power "
    << jsonNumber(options.cost.power) << ", " << table.directions << " directions) along "
    << (table.segments ? "the " + std::to_string(imaging::FodSegmentNorm::kCount) + " lattice directions of order " +
                             std::to_string(imaging::kFodLatticeOrder)
                       : std::string("the 26 neighbour directions"))
    << " of " << withThousands(input.counts.domain) << " domain voxels";
  if (!input.grid.maskDescription.empty()) s << " (mask: " << input.grid.maskDescription << ")";
  s << ", tabulated in " << fixed(table.seconds, 2) << " s (" << fixed(table.cpuSeconds, 2) << " s CPU on "
    << table.threads << (table.threads == 1 ? " thread" : " threads") << ")";
  return s.str();
}

std::string fodWithoutBasisMessage(const std::string& path) {
  try {
    imaging::FodReadOptions probe;
    probe.basis = imaging::shBasisName(imaging::ShBasis::Tournier07);  // any basis: only the layout counts here
    const imaging::FodField fod = imaging::readFodVolume(path, probe);
    if (fod.lmax < 4) return "";
    return path + ": " + std::to_string(fod.coefficientCount()) + " volumes, an FOD image of lmax " +
           std::to_string(fod.lmax) +
           "? state its basis with --fod-basis: mrtrix3 for MRtrix's dwi2fod, DIPY's basis name for its fits "
           "(docs/fod.md)";
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace stvd::tool
