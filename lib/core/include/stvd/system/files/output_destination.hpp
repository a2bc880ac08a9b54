// What an output path names: a regular file (or none yet), which is staged
// next to it and renamed over it; or a stream - a character device such as
// /dev/null or a terminal, a FIFO, or one of the process's own open
// descriptors (/dev/stdout, /dev/stderr, /dev/fd/N, /proc/self/fd/N, or a
// symbolic link to one) - which is written to, never replaced. Sockets and
// block devices are refused.
#pragma once

#include <string>

namespace stvd::files {

struct OutputDestination {
  enum class Kind { File, Stream };
  Kind kind = Kind::File;
  /// For a stream that is one of the process's open descriptors: its
  /// number (written to directly, at its current offset); -1 for a stream
  /// opened by its path (a FIFO, a character device).
  int descriptor = -1;
  /// For messages: "a FIFO", "a character device", "descriptor 1".
  std::string description;

  bool isStream() const { return kind == Kind::Stream; }
};

/// What writing `path` means. Throws OutputError naming `path` for a
/// socket or a block device, and for a descriptor name whose descriptor is
/// not open for writing. Never blocks, never creates anything.
OutputDestination outputDestination(const std::string& path);

/// outputDestination(path).isStream(), false when that throws: for the
/// callers that must not read back what a run wrote to a stream (the QC
/// report takes a scratch copy of such an output instead).
bool isStreamOutput(const std::string& path);

}  // namespace stvd::files
