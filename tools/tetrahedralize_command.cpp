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

  pid_t child = 0;
  const int spawned = ::posix_spawn(&child, helper.c_str(), nullptr, nullptr, childArgv.data(), environ);
  if (spawned != 0)
    throw ToolError(kExitInternal, "tetrahedralize: cannot run " + helper + ": " + std::strerror(spawned));
  int status = 0;
  while (::waitpid(child, &status, 0) < 0) {
    if (errno != EINTR) throw ToolError(kExitInternal, "tetrahedralize: lost the child process: " + std::string(std::strerror(errno)));
  }
  if (WIFEXITED(status)) {
    // The child already printed its one-line message; pass its code on.
    return WEXITSTATUS(status);
  }
  if (WIFSIGNALED(status))
    throw ToolError(kExitInput, "tetrahedralize: TetGen crashed (" + signalName(WTERMSIG(status)) +
                                       "); the surface is probably degenerate or self-intersecting. "
                                       "No output was written");
  throw ToolError(kExitInternal, "tetrahedralize: the child process ended abnormally");
}

}  // namespace stvd::tool
