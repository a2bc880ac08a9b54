// `stvd info`: what a tensor file holds and how stvd reads it: geometry,
// layout, order and frame, eigenvalue and FA statistics, ill-conditioned
// voxels.
#include <algorithm>
#include <optional>
#include <cmath>
#include <iostream>
#include <sstream>

#include "command_line.hpp"
#include "stvd/itk/symmetric_eigen.hpp"
#include "stvd/itk/tensor_frames.hpp"
#include "subcommands.hpp"

namespace stvd::tool {
namespace {

const char* kInfoHelp =
    "Usage: stvd info INPUT [options]\n"
    "\n"
    "Describes a tensor volume as stvd reads it: file layout, component order and frame\n"
    "(stated or the per-format default), grid geometry (LPS as ITK reports it, and RAS),\n"
    "eigenvalue, mean diffusivity and FA statistics over the voxels with a non-zero finite\n"
    "tensor inside the mask, and how many tensors are ill-conditioned. Tensors are reported in\n"
    "the physical LPS frame after the frame conversion; eigenvalues do not depend on the frame.\n"
    "\n"
    "%TENSOR%"
    "  -h, --help              this text.\n"
    "\n"
    "Exit codes: 0 success; 1 internal error; 2 bad command line; 3 unreadable or unusable input.\n";

struct InfoOptions {
  std::string input;
  TensorInputOptions tensor;
};

InfoOptions parseInfoOptions(int argc, char** argv) {
  InfoOptions o;
  ArgumentReader args(argc, argv, 2);
  while (!args.done()) {
    const std::string a = args.take();
    if (takeInputOrHelp(a, args, o.input, kInfoHelp, false)) continue;
    if (a == "--tensor-order" || a == "--tensor-frame" || a == "--mask" || a == "--max-anisotropy") {
      parseTensorInputOption(a, args, o.tensor);
    } else {
      usageError("unknown option '" + a + "' (see stvd info --help)");
    }
  }
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

}  // namespace

int runInfo(int argc, char** argv) {
  const InfoOptions o = parseInfoOptions(argc, argv);
  const TensorInput input = readTensorInput(o.input, o.tensor);
  const imaging::TensorVolume& volume = input.read.volume;
  const imaging::TensorFileInfo& info = input.read.info;
  const GridGeometry& g = volume.geometry;
  const bool nrrd = info.layout == imaging::TensorFileLayout::NrrdSymMatrix ||
                    info.layout == imaging::TensorFileLayout::NrrdMaskedSymMatrix;
  const bool fixedOrder = info.layout != imaging::TensorFileLayout::NiftiSixVolumes;

  std::ostringstream out;
  out << "File:        " << o.input << "\n";
  out << "Layout:      " << imaging::tensorFileLayoutName(info.layout) << ", " << info.componentType
      << " components\n";
  out << "Order:       " << imaging::tensorOrderName(info.order) << " ("
      << imaging::tensorOrderComponents(info.order) << ")"
      << (fixedOrder ? ", fixed by the layout" : ", as stated") << "\n";
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
  std::cout << out.str();
  return kExitOk;
}

}  // namespace stvd::tool
