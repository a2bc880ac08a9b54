// Which files of a run are the same file: an output must never be one of
// the run's inputs, and two outputs must never be one file.
//
// Part of the core library because every entry point (the `stvd` tool, the
// tetrahedralization program, the language bindings) must make the same
// check before it computes anything; POSIX only, no image or mesh format.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "stvd/errors.hpp"

namespace stvd::files {

/// A file a run reads or writes, with what it is to the run, for messages:
/// {"tensor input", "dti.nii.gz"}, {"data file of the distance map",
/// "d.raw.gz"}.
struct RunFile {
  std::string role;
  std::string path;
};

/// True when `a` and `b` name the same file, however they are spelled:
/// when both exist, the same device and inode (which covers "./x",
/// "../dir/x", symbolic links and hard links); otherwise the same canonical
/// path (symbolic links in the existing part of the path resolved, "." and
/// ".." removed).
bool sameFile(const std::string& a, const std::string& b);

/// Throws FileConflict for the first output that is the same file (see
/// sameFile) as an input or as an earlier output, naming both roles.
/// Inputs may repeat (one image as mask and seed labels is fine). List
/// every file: the companions a format reads or writes next to the named
/// file (a detached header's data file, a mesh's .ele and .face files) are
/// entries of their own.
void checkOutputsAreNotInputs(const std::vector<RunFile>& inputs, const std::vector<RunFile>& outputs);

}  // namespace stvd::files
