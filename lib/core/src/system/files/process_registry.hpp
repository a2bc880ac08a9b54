// What the process must clean up when it is stopped by a signal: the staging
// folders of the output transactions in progress and the child processes it
// runs. Private to the files module.
#pragma once

#include <sys/types.h>

#include <mutex>
#include <string>
#include <vector>

namespace stvd::files::detail {

struct ProcessRegistry {
  /// Held while staging folders are created or removed, during a commit,
  /// and by the cleanup on a signal, which therefore never sees half a
  /// commit.
  std::mutex mutex;
  std::vector<std::string> stagingFolders;
  std::vector<pid_t> children;
};

ProcessRegistry& processRegistry();

/// A termination signal that removeStagedOutputsOnTerminationSignals()
/// handles and that has arrived - pending or already taken by its thread -
/// or 0. A commit asks with the registry locked, before its first rename:
/// a signal that arrived before that point is never overtaken by the
/// commit, however late its thread gets to run.
int terminationSignalArrived();

/// What the signal thread does, for a thread that holds the registry's
/// lock: removes the staged outputs, stops the children, prints the
/// interruption line and ends the process by `signal`.
[[noreturn]] void endBySignalWithRegistryLocked(int signal);

}  // namespace stvd::files::detail
