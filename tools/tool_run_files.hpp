// The files one run of a subcommand reads and writes (imaging::RunFiles,
// which the Python package uses as well), with the tool's exit codes and
// TetGen meshes, whose files the imaging adapter does not know.
#pragma once

#include <string>

#include "stvd/imaging/run_files.hpp"

namespace stvd::tool {

class RunFiles : public imaging::RunFiles {
 public:
  /// A TetGen mesh given as its base name or any of its files: .node, .ele
  /// and .face.
  void inputTetMesh(const std::string& role, const std::string& path);

  /// imaging::RunFiles::check, throwing ToolError: kExitUsage when an output
  /// is an input or another output; kExitOutput when an output cannot be
  /// written there.
  void check() const;
};

}  // namespace stvd::tool
