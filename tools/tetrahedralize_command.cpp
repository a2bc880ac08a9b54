// `stvd tetrahedralize`: runs the program stvd-tetrahedralize, installed next
// to `stvd`, as a child process. The program links TetGen (AGPL), which this
// executable must not, and TetGen can crash on degenerate input: a crash of
// the child becomes a one-line error here instead of taking the tool down.
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "stvd/system/files/termination_signals.hpp"
#include "tet_mesh_commands.hpp"

extern char** environ;

namespace stvd::tool {
namespace {

const char* kHelperName = "stvd-tetrahedralize";

std::string signalName(int signal) {
  const char* text = ::strsignal(signal);
  return "signal " + std::to_string(signal) + (text ? std::string(" (") + text + ")" : std::string());
}

}  // namespace

int runTetrahedralize(int argc, char** argv) {
  const std::string helper = executableFolder() + "/" + kHelperName;
  if (::access(helper.c_str(), X_OK) != 0)
    throw ToolError(kExitInternal, "tetrahedralize: " + helper +
                                       " is missing: this stvd was built without TetGen (STVD_WITH_TETGEN, "
                                       "Debian package libtet1.5-dev)");
  std::vector<char*> childArgv;
  childArgv.push_back(const_cast<char*>(kHelperName));
  for (int i = 2; i < argc; ++i) childArgv.push_back(argv[i]);
  childArgv.push_back(nullptr);

  // This process blocks the termination signals for the thread that waits
  // for them (files/termination_signals.hpp); the child starts with none
  // blocked and handles them itself.
  posix_spawnattr_t attributes;
  ::posix_spawnattr_init(&attributes);
  sigset_t none, termination;
  sigemptyset(&none);
  files::handledTerminationSignals(termination);
  ::posix_spawnattr_setsigmask(&attributes, &none);
  ::posix_spawnattr_setsigdefault(&attributes, &termination);
  ::posix_spawnattr_setflags(&attributes, POSIX_SPAWN_SETSIGMASK | POSIX_SPAWN_SETSIGDEF);
  pid_t child = 0;
  const int spawned = ::posix_spawn(&child, helper.c_str(), nullptr, &attributes, childArgv.data(), environ);
  ::posix_spawnattr_destroy(&attributes);
  if (spawned != 0)
    throw ToolError(kExitInternal, "tetrahedralize: cannot run " + helper + ": " + std::strerror(spawned));
  int status = 0;
  {
    const files::ChildProcessGuard stopWithUs(child);
    while (::waitpid(child, &status, 0) < 0) {
      if (errno != EINTR) throw ToolError(kExitInternal, "tetrahedralize: lost the child process: " + std::string(std::strerror(errno)));
    }
  }
  if (WIFEXITED(status)) {
    // The child already printed its one-line message; pass its code on.
    return WEXITSTATUS(status);
  }
  // Told to stop (Ctrl-C reaches the whole process group): the child has
  // removed what it staged; end the same way.
  if (WIFSIGNALED(status) && sigismember(&termination, WTERMSIG(status))) files::endBySignal(WTERMSIG(status));
  if (WIFSIGNALED(status))
    throw ToolError(kExitInput, "tetrahedralize: TetGen crashed (" + signalName(WTERMSIG(status)) +
                                       "); the surface is probably degenerate or self-intersecting. "
                                       "No output was written");
  throw ToolError(kExitInternal, "tetrahedralize: the child process ended abnormally");
}

}  // namespace stvd::tool
