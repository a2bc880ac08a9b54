// `stvd tetrahedralize`: runs the program stvd-tetrahedralize, installed next
// to `stvd`, as a child process. The program links TetGen (AGPL), which this
// executable must not, and TetGen can crash on degenerate input: a crash of
// the child becomes a one-line error here instead of taking the tool down.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <string>
#include <vector>

#include "child_process.hpp"
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
                                       "Debian package libtet1.5-dev), or installed without the AGPL helper "
                                       "(STVD_INSTALL_TETRAHEDRALIZE=ON installs it)");
  // The child reports everything but an interruption itself; the
  // interruption this process reports once the child has ended
  // (files/termination_signals.hpp), naming the command.
  std::vector<std::string> childArguments{kHelperName, "--interruptions-reported-by-parent"};
  childArguments.insert(childArguments.end(), argv + 2, argv + argc);
  std::vector<std::string> environment;
  for (char** e = environ; *e; ++e) environment.emplace_back(*e);
  files::reportInterruptionsAs("stvd tetrahedralize");
  sigset_t termination;
  files::handledTerminationSignals(termination);
  // Started with no signal blocked (child_process.hpp): it handles them
  // itself, and dies with this process.
  ChildProcess child = [&] {
    try {
      return ChildProcess(helper, childArguments, environment);
    } catch (const ToolError& e) {
      throw ToolError(kExitInternal, std::string("tetrahedralize: ") + e.what());
    }
  }();
  const int status = child.wait();
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
