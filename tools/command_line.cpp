#include "command_line.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <sstream>
#include <vector>

#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/imaging/scalar_image.hpp"
#include "stvd/front_end/propagation_choice.hpp"
#include "stvd/itk/tensor_input_io.hpp"

namespace stvd::tool {

void usageError(const std::string& message) { throw ToolError(kExitUsage, message); }

ArgumentReader::ArgumentReader(int argc, char** argv, int first) {
  for (int i = first; i < argc; ++i) args_.emplace_back(argv[i]);
}

bool ArgumentReader::isOption(const std::string& argument) const {
  // "-" alone and negative numbers are values, not options.
  if (argument.size() < 2 || argument[0] != '-') return false;
  return !(std::isdigit(static_cast<unsigned char>(argument[1])) || argument[1] == '.');
}

std::string ArgumentReader::take() {
  inlineValue_.reset();
  std::string argument = args_[next_++];
  if (argument.rfind("--", 0) == 0) {
    const std::size_t equals = argument.find('=');
    if (equals != std::string::npos) {
      inlineValue_ = argument.substr(equals + 1);
      argument.resize(equals);
    }
  }
  return argument;
}

std::string ArgumentReader::value(const std::string& option) {
  if (inlineValue_) {
    std::string v = *inlineValue_;
    inlineValue_.reset();
    return v;
  }
  if (done() || (isOption(args_[next_]) && args_[next_] != "-")) usageError(option + " needs a value");
  return args_[next_++];
}

void ArgumentReader::noValue(const std::string& option) {
  if (inlineValue_) usageError(option + " takes no value");
}

double parseNumber(const std::string& option, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || errno == ERANGE || !std::isfinite(x))
    usageError(option + ": '" + text + "' is not a number");
  return x;
}

int parseInteger(const std::string& option, const std::string& text) {
  errno = 0;
  char* end = nullptr;
  const long x = std::strtol(text.c_str(), &end, 10);
  if (text.empty() || *end != '\0' || errno == ERANGE || x < -2147483647L || x > 2147483647L)
    usageError(option + ": '" + text + "' is not an integer");
  return static_cast<int>(x);
}

namespace {
std::vector<std::string> splitCommas(const std::string& option, const std::string& text) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, ',')) {
    while (!part.empty() && part.front() == ' ') part.erase(part.begin());
    while (!part.empty() && part.back() == ' ') part.pop_back();
    parts.push_back(part);
  }
  if (parts.size() != 3 || text.back() == ',')
    usageError(option + ": '" + text + "' is not three comma-separated numbers");
  return parts;
}
}  // namespace

std::array<double, 3> parseTriple(const std::string& option, const std::string& text) {
  const auto parts = splitCommas(option, text);
  return {parseNumber(option, parts[0]), parseNumber(option, parts[1]), parseNumber(option, parts[2])};
}

std::array<int, 3> parseIntegerTriple(const std::string& option, const std::string& text) {
  const auto parts = splitCommas(option, text);
  return {parseInteger(option, parts[0]), parseInteger(option, parts[1]), parseInteger(option, parts[2])};
}

bool parseTensorInputOption(const std::string& option, ArgumentReader& args, TensorInputOptions& options) {
  using namespace imaging;
  if (option == "--tensor-order") {
    setTensorOrder(options, args.value(option));
  } else if (option == "--tensor-frame") {
    setTensorFrame(options, args.value(option));
  } else if (option == "--tensor-kind") {
    setTensorKind(options, args.value(option));
  } else if (option == "--diffusion-metric") {
    setDiffusionMetric(options, args.value(option));
  } else if (option == "--max-anisotropy") {
    setMaxAnisotropy(options, parseNumber(option, args.value(option)));
  } else if (option == "--fa-threshold") {
    setFaThreshold(options, parseNumber(option, args.value(option)));
  } else if (option == "--mask") {
    options.maskPath = args.value(option);
  } else if (option == "--accept-implausible-tensors") {
    args.noValue(option);
    options.acceptImplausible = true;
  } else {
    return false;
  }
  return true;
}

double parseUnreachableValue(const std::string& option, const std::string& text) {
  if (text == "nan" || text == "NaN") return std::numeric_limits<double>::quiet_NaN();
  const double value = parseNumber(option, text);
  checkUnreachableValue(value, text);
  return value;
}

void checkImageOutputSpelling(const std::string& path) {
  // MRtrix images are written by our own code, in any letter case.
  if (!imaging::hasImageExtension(path) || imaging::isMrtrixImagePath(path)) return;
  for (const char* ext : {".nii", ".nii.gz", ".nrrd", ".nhdr"}) {
    const std::size_t n = std::char_traits<char>::length(ext);
    if (path.size() > n && path.compare(path.size() - n, n, ext) == 0) return;
  }
  usageError(path + ": write the extension in lower case (.nii, .nii.gz, .nrrd or .nhdr)");
}

namespace {
std::vector<std::string>& noted() {
  static std::vector<std::string> warnings;
  return warnings;
}
}  // namespace

void noteInputWarnings(const std::vector<std::string>& lines) {
  for (const std::string& line : lines) {
    if (std::find(noted().begin(), noted().end(), line) != noted().end()) continue;
    noted().push_back(line);
    std::cerr << "stvd: warning: " << line << std::endl;
  }
}

void noteInputWarnings(const std::string& path, const std::vector<std::string>& warnings) {
  std::vector<std::string> lines;
  for (const std::string& w : warnings) lines.push_back(path + ": " + w);
  noteInputWarnings(lines);
}

const std::vector<std::string>& inputWarnings() { return noted(); }

TensorInput readTensorInputNotingWarnings(const std::string& path, const TensorInputOptions& options) {
  TensorInput input = imaging::readTensorInput(path, options);
  noteInputWarnings(input.warnings);
  return input;
}

std::string orientationCode(const GridGeometry& geometry) {
  // LPS components: +x is Left, +y Posterior, +z Superior.
  const char positive[3] = {'L', 'P', 'S'}, negative[3] = {'R', 'A', 'I'};
  std::string code;
  for (int c = 0; c < 3; ++c) {
    int best = 0;
    for (int r = 1; r < 3; ++r)
      if (std::abs(geometry.direction[3 * r + c]) > std::abs(geometry.direction[3 * best + c])) best = r;
    code += geometry.direction[3 * best + c] > 0 ? positive[best] : negative[best];
  }
  return code;
}

std::string tensorInputHelp(bool withMetricOptions) {
  std::string text =
      "Tensor file:\n"
      "  NIfTI (.nii, .nii.gz): the 5D layout X Y Z 1 6 with intent SYMMATRIX (order fixed by the\n"
      "    standard: lower), or six volumes X Y Z 6, whose order must be stated.\n"
      "  NRRD (.nrrd, .nhdr): kind 3D-symmetric-matrix, or 3D-masked-symmetric-matrix whose\n"
      "    confidence channel (>= 0.5) becomes a mask. Order fixed: xx,xy,xz,yy,yz,zz.\n"
      "  MRtrix (.mif, .mif.gz, .mih): X Y Z 6 as dwi2tensor writes it (order mrtrix and the\n"
      "    world frame unless stated).\n"
      "  --tensor-order ORDER    component order of a six-volume NIfTI file (no default):\n"
      "                          lower  = xx,xy,yy,xz,yz,zz (NIfTI standard, DIPY, ANTs; alias nifti)\n"
      "                          fsl    = xx,xy,xz,yy,yz,zz (FSL dtifit; alias upper)\n"
      "                          mrtrix = xx,yy,zz,xy,xz,yz (MRtrix)\n"
      "  --tensor-frame FRAME    frame of the six numbers:\n"
      "                          voxel = along the image index axes i,j,k (DIPY, FSL fits)\n"
      "                          world = NIfTI: RAS scanner axes (MRtrix);\n"
      "                                  NRRD: the measurement frame, in the NRRD space\n"
      "                          default: voxel for NIfTI in the lower and fsl orders, world for\n"
      "                          NIfTI in the mrtrix order and for NRRD.\n"
      "  --mask FILE             only voxels where FILE is non-zero (same grid as the tensors).\n";
  if (withMetricOptions)
    text +=
        "Metric:\n"
        "  --tensor-kind KIND      diffusion (default): the file holds diffusion tensors D;\n"
        "                          metric: the file holds the metric G (cost of a step v is\n"
        "                          sqrt(v^T G v), v in mm).\n"
        "  --diffusion-metric M    inverse (default): G = (D/MD)^-1, MD = trace(D)/3, so isotropic\n"
        "                          tissue costs 1 per mm (O'Donnell et al. 2002);\n"
        "                          adjugate: G = adj(D/MD), anisotropic tissue cheaper still\n"
        "                          (Fuster et al. 2016).\n"
        "  --max-anisotropy A      raise eigenvalues below lambda_max/A to it, which also repairs\n"
        "                          zero and negative eigenvalues (default 100 for diffusion\n"
        "                          tensors; a metric is taken as given, with only zero and\n"
        "                          negative eigenvalues raised to lambda_max/100).\n"
        "  --fa-threshold T        only voxels whose tensor has FA >= T (diffusion tensors).\n"
        "  --accept-implausible-tensors\n"
        "                          go on although more than 10 % of the tensors are not positive\n"
        "                          definite, which a wrong --tensor-order gives (default: exit 3;\n"
        "                          stvd info tries each order).\n"
        "  Voxels with a zero, NaN or infinite tensor, or no positive eigenvalue, are outside.\n";
  else
    text += "  --max-anisotropy A      count tensors with lambda_max/lambda_min above A (default 100).\n";
  return text;
}

std::string jsonString(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\u%04x", c);
      out += buffer;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string jsonNumber(double x) {
  if (!std::isfinite(x)) return "null";
  std::ostringstream s;
  s.precision(10);
  s << x;
  return s.str();
}

std::uint64_t peakMemoryBytes() {
  rusage usage{};
  ::getrusage(RUSAGE_SELF, &usage);
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;  // Linux reports KiB
}

bool takeInputOrHelp(const std::string& argument, const ArgumentReader& args, std::string& input,
                     const char* helpText, bool withMetricOptions) {
  if (!args.isOption(argument)) {
    if (!input.empty()) usageError("more than one input file: '" + input + "' and '" + argument + "'");
    input = argument;
    return true;
  }
  if (argument == "-h" || argument == "--help") {
    std::string help = helpText;
    help.replace(help.find("%TENSOR%"), 8, tensorInputHelp(withMetricOptions));
    std::cout << help;
    throw ToolError(kExitOk, "");
  }
  return false;
}

std::string executableFolder() {
  std::vector<char> buffer(4096);
  const ssize_t n = ::readlink("/proc/self/exe", buffer.data(), buffer.size() - 1);
  if (n <= 0) return ".";
  const std::string path(buffer.data(), static_cast<std::size_t>(n));
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

std::string pythonPackageFolder(const std::string& module) {
#ifdef STVD_PYTHON_INSTALL_DIR
  const std::string here = executableFolder();
  for (const std::string& folder : {here + "/../python", here + "/../" STVD_PYTHON_INSTALL_DIR}) {
    if (::access((folder + "/stvd/" + module).c_str(), R_OK) == 0) return folder;
  }
#else
  (void)module;
#endif
  return {};
}

}  // namespace stvd::tool
