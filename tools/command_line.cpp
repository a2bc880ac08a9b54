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

#include "option_help.hpp"
#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/imaging/scalar_image.hpp"
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

std::string tensorInputHelp(OptionCommand command) {
  std::string text =
      "Tensor file:\n"
      "  NIfTI (.nii, .nii.gz): the 5D layout X Y Z 1 6 with intent SYMMATRIX (order fixed by the\n"
      "    standard: lower), or six volumes X Y Z 6, whose order must be stated.\n"
      "  NRRD (.nrrd, .nhdr): kind 3D-symmetric-matrix, or 3D-masked-symmetric-matrix whose\n"
      "    confidence channel (>= 0.5) becomes a mask. Order fixed: xx,xy,xz,yy,yz,zz.\n"
      "  MRtrix (.mif, .mif.gz, .mih): X Y Z 6 as dwi2tensor writes it, or X Y Z 1 6 as mrconvert\n"
      "    makes it from a NIfTI 5D file (order mrtrix and the world frame unless stated).\n" +
      optionHelp(command, {OptionGroup::TensorFile});
  // stvd info takes --max-anisotropy only, for its count of tensors beyond it.
  if (!toolOption("--tensor-kind").takes(command)) return text + optionHelp(command, {OptionGroup::Metric});
  return text + "Metric:\n" + optionHelp(command, {OptionGroup::Metric}) +
         "  Voxels with a zero, NaN or infinite tensor, or no positive eigenvalue, are outside.\n";
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
  // The build tree, the install prefix, and a wheel of `pip install .`
  // (the tool is stvd/_bin/stvd inside the installed package).
  for (const std::string& folder : {here + "/../python", here + "/../" STVD_PYTHON_INSTALL_DIR, here + "/../.."}) {
    if (::access((folder + "/stvd/" + module).c_str(), R_OK) == 0) return folder;
  }
#else
  (void)module;
#endif
  return {};
}

}  // namespace stvd::tool
