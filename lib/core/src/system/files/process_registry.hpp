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

}  // namespace stvd::files::detail
