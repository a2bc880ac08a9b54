// The outputs of one run, written all or nothing.
//
// Each output is written into a private staging folder next to its final
// path (".stvd-staging-<pid>-<n>" in the output's folder, so that the final
// rename never crosses a file system), together with any file the writer
// puts next to it (the data file of a detached NRRD header). Only when every
// output of the run has been written and flushed to disk are they moved
// into place, by rename; a file they replace is kept until all renames have
// succeeded and restored when one fails. Whatever goes wrong before the
// commit - a writer's error, a full disk, a file-size limit, an exception
// anywhere in the run - the staging folders are removed and every file
// that was at an output path before stays as it was. A file an output
// replaces passes its mode bits and group (and, for root, its owner) on to
// the new file.
//
// An output path that names a stream - a character device (/dev/null, a
// terminal), a FIFO, or one of the process's open descriptors
// (/dev/stdout, /dev/fd/N: output_destination.hpp) - is never replaced: it
// is staged in the temporary folder like the others, and at the commit
// written to the stream, before any file is moved into place (a stream
// that cannot be written leaves the files as they were; what a stream has
// taken cannot be taken back). Sockets and block devices are refused.
//
// Each staging folder holds a record of the process that made it
// (staging_record.hpp); a folder of a process that is gone (killed with
// SIGKILL, say) is removed the next time an output is staged in its folder.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "stvd/errors.hpp"

namespace stvd::files {

/// Throws OutputError naming `path` when it cannot become an output file:
/// its folder does not exist, is not a folder, or is not writable, or
/// `path` names an existing folder, a socket or a block device, or a
/// stream that cannot be written to. Lets a run fail before long work, not
/// after it.
void checkOutputPath(const std::string& path);

class OutputTransaction {
 public:
  /// Writes one output into `stagingPath`: the staging folder plus the
  /// output's own file name. It may add files next to it (companions),
  /// which are moved into the output's folder with it. It reports failure
  /// by throwing; a writer must check every write it makes (stream state,
  /// sizes a library does not report).
  using Writer = std::function<void(const std::string& stagingPath)>;

  OutputTransaction();
  /// Without commit(), removes everything staged: no file of the run
  /// appears and none is replaced.
  ~OutputTransaction();
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;

  /// Checks `path` (checkOutputPath), creates its staging folder, runs
  /// `writer` and flushes what it wrote to disk (fsync). A failure of the
  /// writer (any std::runtime_error) or of the flush is thrown as
  /// OutputError naming `path`, with staging paths in the writer's message
  /// replaced by final ones. Other exceptions (std::logic_error, bad_alloc)
  /// pass unchanged. A failed output is removed at once (the others stay
  /// staged). Throws OutputError when `path` was written before in this
  /// transaction.
  void write(const std::string& path, const Writer& writer);

  /// Moves every staged file into place (per output: companions first, the
  /// named file last), then flushes the output folders. When a rename
  /// fails, those done are undone (the replaced files restored) and
  /// OutputError is thrown. With removeStagedOutputsOnTerminationSignals()
  /// in force, a termination signal that has arrived by the time the
  /// replaced files are kept - even one its thread has not yet taken -
  /// ends the process before the first rename, nothing committed; one that
  /// arrives later waits until every file is in place.
  void commit();

 private:
  struct Staged;
  std::vector<std::unique_ptr<Staged>> staged_;
  bool committed_ = false;
};

/// What the name of every staging folder starts with: the prefix, the
/// process id, '-' and a counter.
inline constexpr const char* kStagingFolderPrefix = ".stvd-staging-";

/// Removes the staging folders, and what is in them, that runs killed
/// before they could clean up (SIGKILL, the OOM killer) left in `folder`;
/// returns how many. Only folders that are demonstrably such leftovers are
/// removed: named as ours, owned by this user, holding the record a run of
/// ours writes into each, which names a process of this machine, boot and
/// pid namespace that no longer exists (its id unused, reused by a process
/// started at another time, or a zombie). Anything else stays: a folder
/// without that record, another machine's (an NFS folder), a live run's.
/// Safe while other runs write into the folder. OutputTransaction calls it
/// once per folder and process before it stages there. Throws OutputError
/// naming `folder` when it cannot be listed or a leftover cannot be
/// removed.
std::size_t removeLeftoverStagingFolders(const std::string& folder);

/// Writes one output on its own: an OutputTransaction with this output
/// alone, committed. What the plain-path writers of the adapters use.
void writeAtomically(const std::string& path, const OutputTransaction::Writer& writer);

}  // namespace stvd::files
