// `stvd info`: what a tensor file holds and how stvd reads it: geometry,
// layout, order and frame, eigenvalue and FA statistics, ill-conditioned
// voxels.
#include <algorithm>
#include <optional>
#include <cmath>
#include <iostream>
#include <sstream>

#include "command_line.hpp"
#include "command_options.hpp"
#include "geodesic_options.hpp"
#include "stvd/imaging/symmetric_eigen.hpp"
#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/imaging/tensor_frame_check.hpp"
#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/imaging/tensor_plausibility.hpp"
#include "option_help.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "subcommands.hpp"

namespace stvd::tool {
namespace {

std::string infoHelp() {
  return "Usage: stvd info INPUT [options]\n"
         "\n"
         "Describes a tensor volume as stvd reads it: file layout, component order and frame\n"
         "(stated or the per-format default), grid geometry (LPS as ITK reports it, and RAS),\n"
         "eigenvalue, mean diffusivity and FA statistics over the voxels with a non-zero finite\n"
         "tensor inside the mask, and how many tensors are ill-conditioned. Tensors are reported in\n"
         "the physical LPS frame after the frame conversion; eigenvalues do not depend on the frame.\n"
         "\n" +
         tensorInputHelp(kInfoCommand) + optionHelp(kInfoCommand, {OptionGroup::Output}) +
         "\n"
         "Voxel indices: stvd's --seed-voxel and --target-voxel count the axes as the file stores\n"
         "them (NIfTI, ITK, nibabel). MRtrix (mrview, mrconvert -coord) reorders the axes of every\n"
         "image to point right, anterior, superior, so its indices can differ (the shipped brain's\n"
         "voxel 55,54,15 is 56,54,15 in MRtrix); `Voxel indices:` says how. --seed-point X,Y,Z in\n"
         "scanner millimetres is the same point in every tool.\n"
         "\n"
         "Exit codes: 0 success; 1 internal error; 2 bad command line; 3 unreadable or unusable input;\n"
         "4 a --voxel outside the image.\n";
}

struct InfoOptions {
  std::string input;
  TensorInputOptions tensor;
  std::vector<std::array<int, 3>> voxels;  // --voxel
};

InfoOptions parseInfoOptions(int argc, char** argv) {
  const CommandLine line = readCommandLine(kInfoCommand, argc, argv, 2, infoHelp);
  InfoOptions o;
  o.input = line.input;
  o.tensor = imaging::tensorInputOptionsOf(line.values);
  o.voxels = imaging::voxelsOf(line.values, "--voxel");
  if (o.input.empty()) usageError("no input file (see stvd info --help)");
  return o;
}

/// Minimum, 1st percentile, median, 99th percentile and maximum.
std::string percentiles(std::vector<double> values, int precision, bool scientific) {
  if (values.empty()) return "(none)";
  std::sort(values.begin(), values.end());
  auto at = [&](double q) { return values[static_cast<std::size_t>(q * (values.size() - 1) + 0.5)]; };
  std::ostringstream s;
  s.precision(precision);
  if (scientific) s.setf(std::ios::scientific);
  else s.setf(std::ios::fixed);
  s << "min " << values.front() << ", p1 " << at(0.01) << ", median " << at(0.5) << ", p99 " << at(0.99)
    << ", max " << values.back();
  return s.str();
}

std::string matrixRows(const imaging::Matrix3& m) {
  std::ostringstream s;
  for (int r = 0; r < 3; ++r) {
    s << "    [";
    for (int c = 0; c < 3; ++c) s << (c ? " " : "") << (m[3 * r + c] >= 0 ? " " : "") << fixed(m[3 * r + c], 6);
    s << "]\n";
  }
  return s.str();
}

/// How MRtrix numbers the voxels stvd numbers (i, j, k), and the voxels
/// asked for with --voxel in both numberings.
std::string voxelIndexReport(const InfoOptions& o, const GridGeometry& g) {
  const imaging::MrtrixAxisOrder order = imaging::mrtrixAxisOrder(g);
  std::ostringstream out;
  out << "Voxel indices: stvd's (i, j, k) count the axes as stored; MRtrix (mrview, mrconvert -coord) shows (";
  for (int r = 0; r < 3; ++r) {
    const int a = order.axis[r];
    out << (r ? ", " : "") << (order.reversed[r] ? std::to_string(g.size[a] - 1) + " - " : std::string())
        << "ijk"[a];
  }
  out << ")\n";
  for (const auto& v : o.voxels) {
    for (int a = 0; a < 3; ++a)
      if (v[a] < 0 || v[a] >= static_cast<long>(g.size[a]))
        throw ToolError(kExitDomain, o.input + ": voxel " + voxelText({v[0], v[1], v[2]}) +
                                         " lies outside the image (indices from 0)");
    const auto shown = imaging::mrtrixVoxelIndex(g, {v[0], v[1], v[2]});
    const Vec3d lps = g.indexToPhysicalPoint(v[0], v[1], v[2]);
    out << "Voxel:       " << voxelText({v[0], v[1], v[2]}) << " in stvd = (" << shown[0] << ", " << shown[1]
        << ", " << shown[2] << ") in MRtrix, at RAS (" << fixed(-lps.x, 2) << ", " << fixed(-lps.y, 2) << ", "
        << fixed(lps.z, 2) << ") mm\n";
  }
  return out.str();
}

/// The three component orders tried on the file, and what the order as
/// read looks like: a wrong order leaves most tensors not positive definite.
std::string componentOrderReport(const TensorInput& input, std::size_t considered) {
  const imaging::TensorFileInfo& info = input.read.info;
  std::ostringstream out;
  out << "Component orders tried (tensors positive definite, of the " << withThousands(considered)
      << " with a value):\n";
  const imaging::TensorOrder* best = nullptr;
  std::uint64_t bestCount = 0, notPositiveDefinite = 0;
  const auto trials = imaging::tryComponentOrders(input.read, input.mask);
  for (const imaging::ComponentOrderTrial& t : trials) {
    const std::string name = imaging::tensorOrderName(t.order);
    out << "  " << name << std::string(8 - name.size(), ' ') << imaging::tensorOrderComponents(t.order) << "  "
        << withThousands(t.positiveDefinite) << " ("
        << fixed(t.tensors ? 100.0 * double(t.positiveDefinite) / double(t.tensors) : 0.0, 1) << " %), FA above 1 in "
        << withThousands(t.faAboveOne) << (t.order == info.order ? "   <- as read" : "") << "\n";
    if (t.order == info.order) notPositiveDefinite = t.tensors - t.positiveDefinite;
    if (!best || t.positiveDefinite > bestCount) {
      best = &t.order;
      bestCount = t.positiveDefinite;
    }
  }
  if (considered > 0 && double(notPositiveDefinite) > imaging::kMaxNotPositiveDefiniteShare * double(considered)) {
    out << "Warning: read as " << imaging::tensorOrderName(info.order) << ", "
        << fixed(100.0 * double(notPositiveDefinite) / double(considered), 1)
        << " % of the tensors are not positive definite; stvd distance, path and connectivity stop on such a file"
           " (exit 3) unless --accept-implausible-tensors is given.";
    if (best && *best != info.order)
      out << " The order " << imaging::tensorOrderName(*best) << " gives " << withThousands(bestCount)
          << " positive definite tensors: try --tensor-order " << imaging::tensorOrderName(*best) << ".";
    out << "\n";
  }
  return out.str();
}

/// Which frame the principal directions fit best (tensor_frame_check.hpp):
/// the frame as read, and the best ones, by mean streamline length.
std::string frameReport(const TensorInput& input) {
  const imaging::TensorFrameCheck check =
      imaging::checkTensorFrame(input.read.volume.tensors, input.read.volume.geometry, input.mask);
  std::ostringstream out;
  out << "Frame check: " << imaging::tensorFrameCheckSummary(check) << "\n";
  if (check.seeds == 0 || check.trials.empty() || check.trials.front().meanLengthMm == 0.0) return out.str();
  out << "  mean streamline of the principal direction (diffusion tensors) with the components along i, j, k "
         "as below, best first (a frame and its negative give the same tensors):\n";
  for (std::size_t n = 0; n < check.trials.size(); ++n) {
    const imaging::TensorFrameTrial& t = check.trials[n];
    if (n >= 5 && !t.transform.isIdentity()) continue;
    const std::string text = imaging::axisTransformText(t.transform);
    const std::string words = imaging::axisTransformWords(t.transform);
    out << "  " << text << std::string(text.size() < 14 ? 14 - text.size() : 1, ' ') << fixed(t.meanLengthMm, 1)
        << " mm  " << words << (t.transform.isIdentity() ? "   <- as read" : "") << "\n";
  }
  if (check.verdict == imaging::TensorFrameVerdict::Mismatch)
    out << "Warning: the components fit the image " << imaging::axisTransformWords(check.best) << " "
        << imaging::axisTransformText(check.best)
        << ", not as read; stvd distance, path and connectivity stop on such a file (exit 3) unless "
           "--accept-misaligned-tensors is given. Rotate the components with the image axes (an image reoriented "
           "by nibabel.as_closest_canonical, say, keeps its components as they were).\n";
  return out.str();
}

}  // namespace

int runInfo(int argc, char** argv) {
  const InfoOptions o = parseInfoOptions(argc, argv);
  const TensorInput input = readTensorInputNotingWarnings(o.input, o.tensor);
  const imaging::TensorVolume& volume = input.read.volume;
  const imaging::TensorFileInfo& info = input.read.info;
  const GridGeometry& g = volume.geometry;
  const bool nrrd = info.layout == imaging::TensorFileLayout::NrrdSymMatrix ||
                    info.layout == imaging::TensorFileLayout::NrrdMaskedSymMatrix;
  const bool mrtrixImage = info.layout == imaging::TensorFileLayout::MrtrixSixVolumes;
  const bool fixedOrder = info.layout != imaging::TensorFileLayout::NiftiSixVolumes && !mrtrixImage;

  std::ostringstream out;
  out << "File:        " << o.input << "\n";
  out << "Layout:      " << imaging::tensorFileLayoutName(info.layout) << ", " << info.componentType
      << " components\n";
  out << "Order:       " << imaging::tensorOrderName(info.order) << " ("
      << imaging::tensorOrderComponents(info.order) << ")"
      << (fixedOrder                        ? ", fixed by the layout"
          : mrtrixImage && !o.tensor.order ? ", MRtrix's tensor convention (default for MRtrix images)"
                                            : ", as stated")
      << "\n";
  out << "Frame:       " << imaging::tensorFrameName(info.frame)
      << (info.frameWasStated ? " (as stated)" : " (default for this layout and order)") << ": ";
  if (info.frame == imaging::TensorFrame::Voxel)
    out << "components along the index axes i, j, k\n";
  else if (nrrd)
    out << (info.hasMeasurementFrame ? "components in the measurement frame" : "components in the NRRD space (no measurement frame)")
        << "\n";
  else
    out << "components along the RAS scanner axes\n";
  if (nrrd) {
    out << "NRRD space:  " << (info.nrrdSpace.empty() ? "(none)" : info.nrrdSpace) << "\n";
    if (info.hasMeasurementFrame)
      out << "Measurement frame in LPS (columns are the frame's axes):\n" << matrixRows(info.measurementFrameLps);
  }
  out << "Grid:        " << g.size[0] << " x " << g.size[1] << " x " << g.size[2] << " voxels, spacing "
      << fixed(g.spacing[0], 4) << " x " << fixed(g.spacing[1], 4) << " x " << fixed(g.spacing[2], 4) << " mm\n";
  out << "Orientation: " << orientationCode(g) << " (RAS letters the i, j, k axes point to), oblique by "
      << fixed(imaging::obliquityDegrees(g), 2) << " degrees\n";
  out << "Origin:      LPS (" << fixed(g.origin[0], 3) << ", " << fixed(g.origin[1], 3) << ", "
      << fixed(g.origin[2], 3) << ") mm = RAS (" << fixed(-g.origin[0], 3) << ", " << fixed(-g.origin[1], 3)
      << ", " << fixed(g.origin[2], 3) << ") mm\n";
  out << "Direction cosines in LPS (columns are the i, j, k axes):\n" << matrixRows(g.direction);
  out << voxelIndexReport(o, g);
  if (!input.maskDescription.empty()) out << "Mask:        " << input.maskDescription << "\n";

  std::size_t masked = 0, zero = 0, nonFinite = 0, considered = 0;
  std::size_t noPositive = 0, nonPositiveSmallest = 0, beyondCap = 0, faAboveOne = 0;
  std::vector<double> l1, l2, l3, md, fa;
  // A metric taken as given has no cap: only non-positive eigenvalues are
  // raised, to lambda1/100, which is what the counts below report then.
  const std::optional<double> givenCap = imaging::anisotropyCap(o.tensor.metric);
  const double cap = givenCap.value_or(imaging::kDefaultMaxAnisotropy);
  for (std::size_t v = 0; v < volume.tensors.size(); ++v) {
    if (!input.mask.empty() && input.mask[v] == 0) { ++masked; continue; }
    const SymTensor3& t = volume.tensors[v];
    const float c[6] = {t.xx, t.xy, t.xz, t.yy, t.yz, t.zz};
    if (!std::all_of(c, c + 6, [](float x) { return std::isfinite(x); })) { ++nonFinite; continue; }
    if (std::all_of(c, c + 6, [](float x) { return x == 0.f; })) { ++zero; continue; }
    ++considered;
    const imaging::SymmetricEigen e = imaging::eigenDecompose(t);
    l1.push_back(e.values[0]);
    l2.push_back(e.values[1]);
    l3.push_back(e.values[2]);
    md.push_back((e.values[0] + e.values[1] + e.values[2]) / 3.0);
    const double f = imaging::fractionalAnisotropy(e.values);
    fa.push_back(f);
    if (f > 1.0) ++faAboveOne;
    if (!(e.values[0] > 0.0)) ++noPositive;
    else if (e.values[2] <= 0.0) ++nonPositiveSmallest;
    else if (givenCap && e.values[0] / e.values[2] > cap) ++beyondCap;
  }
  out << "Voxels:      " << withThousands(volume.tensors.size()) << " in all; " << withThousands(considered)
      << " with a non-zero finite tensor" << (input.mask.empty() ? "" : " inside the mask") << "; "
      << withThousands(zero) << " zero, " << withThousands(nonFinite) << " non-finite";
  if (!input.mask.empty()) out << ", " << withThousands(masked) << " masked out";
  out << "\n";
  out << "Statistics over the " << withThousands(considered) << " voxels with a tensor:\n";
  out << "  lambda1    " << percentiles(l1, 3, true) << "\n";
  out << "  lambda2    " << percentiles(l2, 3, true) << "\n";
  out << "  lambda3    " << percentiles(l3, 3, true) << "\n";
  out << "  MD         " << percentiles(md, 3, true) << "\n";
  out << "  FA         " << percentiles(fa, 3, false) << (faAboveOne ? " (" + withThousands(faAboveOne) + " above 1: negative eigenvalues)" : "")
      << "\n";
  out << "Ill-conditioned: " << withThousands(nonPositiveSmallest + beyondCap + noPositive) << " voxels: "
      << withThousands(nonPositiveSmallest) << " with a zero or negative smallest eigenvalue, "
      << withThousands(beyondCap) << " with lambda1/lambda3 > " << (givenCap ? fixed(cap, 0) : std::string("the cap (none)"))
      << ", " << withThousands(noPositive) << " without a positive eigenvalue.\n";
  out << "  stvd distance raises the eigenvalues of the first two kinds to lambda1/" << fixed(cap, 0)
      << (givenCap ? " (--max-anisotropy)" : " (a metric is otherwise taken as given)")
      << " and leaves the last kind, zero and non-finite tensors outside the domain.\n";
  out << componentOrderReport(input, considered);
  out << frameReport(input);
  std::cout << out.str();
  return kExitOk;
}

}  // namespace stvd::tool
