// Reading a file that someone else may have put in a shared folder: only a
// regular file is read. A FIFO blocks the reader until someone writes to it,
// and a device such as /dev/zero (or a link to it named like an input) can be
// read from for ever; both are refused with a message instead. The file is
// opened without blocking and checked on the open descriptor (fstat), so
// that nothing can be swapped in between the check and the reading.
#pragma once

#include <sys/types.h>

#include <cstdint>
#include <limits>
#include <string>

#include "stvd/errors.hpp"

namespace stvd::files {

/// "a FIFO", "a character device", "a socket", "a folder", ... for messages.
std::string fileKindName(mode_t mode);

/// A regular file open for reading (after following symbolic links),
/// closed when it goes out of scope.
class RegularFile {
 public:
  /// Opens `path` with O_NONBLOCK (a FIFO without a writer does not block
  /// the open), checks with fstat that it is a regular file, and makes the
  /// descriptor blocking again. Throws InputFileError (stvd/errors.hpp):
  /// "no such file", "is a FIFO, not a regular file", "cannot open:
  /// Permission denied", ...
  explicit RegularFile(const std::string& path);
  ~RegularFile();
  RegularFile(const RegularFile&) = delete;
  RegularFile& operator=(const RegularFile&) = delete;

  int descriptor() const { return fd_; }
  /// The size fstat gave when the file was opened.
  std::uint64_t size() const { return size_; }
  /// Hands the descriptor over (to gzdopen, say): it is no longer closed here.
  int release();

 private:
  int fd_ = -1;
  std::uint64_t size_ = 0;
};

/// True when `path` can be opened as a regular file (RegularFile would not
/// throw). Never blocks.
bool isReadableRegularFile(const std::string& path);

/// The whole content of the regular file `path`, or its first `maxBytes`
/// bytes when `truncate` is set; otherwise a file larger than `maxBytes`
/// is refused (InputFileError "is larger than N bytes"). Reads what the
/// file holds when it is read, however its size changes meanwhile, never
/// more than `maxBytes`.
std::string readRegularFile(const std::string& path,
                            std::uint64_t maxBytes = std::numeric_limits<std::uint64_t>::max(),
                            bool truncate = false);

}  // namespace stvd::files
