// What the subcommands of `stvd` share: exit codes, the error that carries
// one, a small argument reader (command_options.hpp reads command lines with
// it) and the help on tensor files.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "stvd/imaging/tensor_input.hpp"
#include "stvd/imaging/tensor_layout.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/imaging/tensor_volume.hpp"
#include "stvd/front_end/number_text.hpp"
#include "stvd/front_end/option_declarations.hpp"

namespace stvd::tool {

/// Exit codes of every subcommand (documented in docs/cli.md and --help).
enum ExitCode : int {
  kExitOk = 0,
  kExitInternal = 1,  ///< an unexpected failure (a bug: please report it)
  kExitUsage = 2,     ///< bad command line: unknown option, bad value, missing argument
  kExitInput = 3,     ///< an input file cannot be read or used (format, layout, geometry)
  kExitDomain = 4,    ///< nothing to compute: empty domain, seed outside the image or domain
  kExitOutput = 5,    ///< an output file cannot be written
  kExitMemory = 6,    ///< the run needs more memory than is available
};

/// A failure with its exit code; what() is the one-line message.
class ToolError : public std::runtime_error {
 public:
  ToolError(int exitCode, const std::string& message) : std::runtime_error(message), exitCode_(exitCode) {}
  int exitCode() const { return exitCode_; }

 private:
  int exitCode_;
};

/// Throws ToolError(kExitUsage, message).
[[noreturn]] void usageError(const std::string& message);

/// Walks over argv. Options are "--name value", "--name=value" or a flag
/// "--name"; anything not starting with '-' is positional.
class ArgumentReader {
 public:
  ArgumentReader(int argc, char** argv, int first);
  bool done() const { return next_ >= args_.size(); }
  /// The next argument, and whether it is an option. For "--name=value"
  /// the option is "--name" and the value is kept for value().
  std::string take();
  bool isOption(const std::string& argument) const;
  /// The value of the option just taken; usage error when there is none.
  std::string value(const std::string& option);
  /// Usage error when the option just taken came with "=value".
  void noValue(const std::string& option);

 private:
  std::vector<std::string> args_;
  std::size_t next_ = 0;
  std::optional<std::string> inlineValue_;
};

// How to read a tensor file and turn it into a metric, and the tensors with
// their mask (stvd/imaging/tensor_input.hpp). The library's readers throw
// ImageIoError and InputError, which main() reports with kExitInput.
using imaging::TensorInput;
using imaging::TensorInputOptions;

/// imaging::readTensorInput, noting the warnings about the files it read.
TensorInput readTensorInputNotingWarnings(const std::string& path, const TensorInputOptions& options);

/// An image output path whose extension ITK's writers will recognise: they
/// take .nii, .nii.gz, .nrrd and .nhdr in lower case only, so "D.NII.GZ"
/// is a usage error here rather than a failed write after the computation
/// (.mif and .mif.gz, written by stvd itself, may be spelt in any case).
void checkImageOutputSpelling(const std::string& path);

/// Says each warning about an input file once, in the tool's words, as a
/// line "stvd: warning: FILE: text" on stderr (also with --quiet: it is
/// about the data, not progress), and keeps it for inputWarnings().
void noteInputWarnings(const std::string& path, const std::vector<std::string>& warnings);
/// The same for warnings that name their file already ("FILE: text").
void noteInputWarnings(const std::vector<std::string>& lines);
/// Every warning noted so far, each "FILE: text", for --stats.
const std::vector<std::string>& inputWarnings();

/// "LAS"-style orientation code: the RAS direction each index axis points
/// to most (L/R, P/A, I/S), as NIfTI tools print it.
std::string orientationCode(const GridGeometry& geometry);

/// The help's section on tensor files: the formats, then the options of
/// the tensor file and the metric that `command` takes (option_help.hpp).
std::string tensorInputHelp(OptionCommand command);

/// The folder of the running executable (from /proc/self/exe): where the
/// programs and packages that `stvd` runs are found relative to it.
std::string executableFolder();

/// The folder that holds the Python package stvd (with its module `module`,
/// such as "cohort.py") for this executable: <build>/python next to
/// <build>/tools/stvd, or <prefix>/lib/python3.X/dist-packages next to
/// <prefix>/bin/stvd. Empty when neither holds it (a package installed by
/// pip, which the interpreter finds itself) or the tool was built without
/// the package.
std::string pythonPackageFolder(const std::string& module);

// Numbers in messages and reports, as the library writes them.
using text::fixed;
using text::withThousands;
/// A JSON string literal (quotes and control characters escaped).
std::string jsonString(const std::string& s);
/// A JSON number with 10 significant digits; null for NaN and infinities.
std::string jsonNumber(double x);
/// The peak resident set size of the process (getrusage), in bytes.
std::uint64_t peakMemoryBytes();

}  // namespace stvd::tool
