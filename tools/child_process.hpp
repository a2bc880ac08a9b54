// Every process the tool starts (the Python report, stvd-tetrahedralize)
// starts the same way: with no signal blocked and the termination signals
// at their default action (the tool itself blocks them for the thread that
// waits for them, and a blocked mask survives exec), stopped when the tool
// is (ChildProcessGuard, files/termination_signals.hpp), and killed by the
// kernel if the tool dies without stopping it (SIGKILL, the OOM killer).
// And the Python child runs isolated from the folder it is started in, the
// user's site packages and the PYTHON* variables (docs/reliability.md,
// "Processes, signals and network").
#pragma once

#include <sys/types.h>

#include <memory>
#include <string>
#include <vector>

#include "stvd/system/files/termination_signals.hpp"

namespace stvd::tool {

/// Where a child's standard input and error come from; -1: the tool's own.
struct ChildStreams {
  int input = -1;
  int errors = -1;
};

/// A running child process, guarded from its start: a termination signal
/// to the tool is passed on to it and waited for. Throws ToolError
/// (internal) naming `program` when it cannot be started. `program` is
/// looked up in the absolute folders of PATH when it has no slash (never
/// in the working folder).
class ChildProcess {
 public:
  ChildProcess(const std::string& program, const std::vector<std::string>& arguments,
               const std::vector<std::string>& environment, ChildStreams streams = {});
  pid_t pid() const { return pid_; }
  /// Waits for it to end (retrying on EINTR) and ends the guarding; its
  /// wait status. Call it once.
  int wait();

 private:
  pid_t pid_ = -1;
  std::unique_ptr<files::ChildProcessGuard> guard_;
};

/// In the child, after fork, before exec (async-signal-safe calls only):
/// every signal unblocked, the termination signals at their default
/// action, SIGTERM when the parent dies. Also for a process that execs in
/// its own place (`stvd cohort`), with `parentDeath` false.
void prepareSignalsForExec(bool parentDeath);

/// The command running `python -m MODULE ARGUMENTS` isolated: `python -I`
/// (no working or script folder on sys.path, no user site packages, no
/// PYTHON* variables), with `packageFolder` (the folder holding the package
/// stvd next to this tool; empty: the interpreter's own) put first on
/// sys.path by a bootstrap given with -c.
std::vector<std::string> isolatedPythonCommand(const std::string& interpreter, const std::string& packageFolder,
                                               const std::string& module,
                                               const std::vector<std::string>& arguments);

}  // namespace stvd::tool
