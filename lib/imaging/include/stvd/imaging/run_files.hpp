// The files one run reads and writes, declared before anything is read or
// computed: no output may be an input (or one of the files an input brings
// with it), no two outputs may be one file, and every output must be
// writable. The check every entry point makes - the `stvd` tool's
// subcommands and the Python package's writers - in one place.
#pragma once

#include <string>
#include <vector>

#include "stvd/system/files/file_identity.hpp"

namespace stvd::imaging {

class RunFiles {
 public:
  /// An image input: the file and the files it brings (a NRRD or MRtrix
  /// .mih header's data files, the other half of a NIfTI pair). Nothing for
  /// an empty path.
  void inputImage(const std::string& role, const std::string& path);
  /// Any other input file. Nothing for an empty path.
  void inputFile(const std::string& role, const std::string& path);

  /// An image output and the files writing it creates (a .nhdr header's
  /// data file). Nothing for an empty path.
  void outputImage(const std::string& role, const std::string& path);
  /// Any other output file. Nothing for an empty path.
  void outputFile(const std::string& role, const std::string& path);

  /// Throws files::FileConflict when an output is an input or another
  /// output ("<path>: the distance map is the tensor input ..."), and
  /// files::OutputError or ImageIoError naming the output when its folder
  /// is missing or not writable, or when writing an image would replace an
  /// unrelated file next to it. All one line.
  void check() const;

  const std::vector<files::RunFile>& inputs() const { return inputs_; }
  const std::vector<files::RunFile>& outputs() const { return outputs_; }

 private:
  std::vector<files::RunFile> inputs_, outputs_;
  std::vector<std::string> imageOutputs_;
};

}  // namespace stvd::imaging
