// What a program does when it is told to stop (SIGINT from Ctrl-C, SIGTERM
// from a job scheduler, SIGHUP when its terminal goes away): remove every
// output it has staged but not committed, stop the child processes it runs,
// and end by the same signal, so that a shell reports 128 + the signal
// number (130, 143, 129) and a script loop around it stops as well.
#pragma once

#include <signal.h>
#include <sys/types.h>

#include <functional>
#include <string>

namespace stvd::files {

/// Blocks SIGINT, SIGTERM and SIGHUP in the calling thread and in every
/// thread it creates afterwards, and starts a thread that waits for them
/// (signalfd), named "stvd-signals" (/proc/PID/task/*/comm): once it shows,
/// a termination signal is handled. Call it first in main(), before any
/// other thread exists.
/// Signals whose disposition is "ignore" when it is called (a program
/// started in the background by a non-interactive shell ignores SIGINT)
/// stay ignored. On a signal the thread waits for a commit in progress to
/// finish (a commit that has not yet moved a file gives way to the signal
/// instead: OutputTransaction::commit), then sends the signal to the registered child processes and
/// waits for them to end (a second termination signal meanwhile kills them
/// with SIGKILL), removes the staging folders of every OutputTransaction,
/// prints "<programName>: interrupted (SIGINT)" on stderr (unless
/// `programName` is empty) and ends the process by the signal. The line is
/// printed after every child has ended: nothing of the run is committed
/// after it. Calling it again does nothing.
void removeStagedOutputsOnTerminationSignals(const std::string& programName);

/// The program name of that line from now on (a command that runs another
/// program in a child process names the command: "stvd tetrahedralize").
void reportInterruptionsAs(const std::string& programName);

/// The signals removeStagedOutputsOnTerminationSignals() handles (empty
/// before it is called): a child process must start with them unblocked
/// and at their default action, so that it can handle them itself (a
/// process that execs another program in its own place unblocks them
/// first).
void handledTerminationSignals(sigset_t& signals);

/// While it lives, the child process is sent the termination signal the
/// program receives, and waited for, before the program ends.
class ChildProcessGuard {
 public:
  explicit ChildProcessGuard(pid_t child);
  /// Calls `start`, which starts a child process and returns its id (or
  /// throws), while a termination signal waits: no signal finds the child
  /// started but not yet guarded.
  explicit ChildProcessGuard(const std::function<pid_t()>& start);
  ~ChildProcessGuard();
  ChildProcessGuard(const ChildProcessGuard&) = delete;
  ChildProcessGuard& operator=(const ChildProcessGuard&) = delete;
  pid_t pid() const { return child_; }

 private:
  pid_t child_;
};

/// Writes `text` (a progress bar's line) on stderr in one write, unless the
/// program is ending by a termination signal: the interruption line is then
/// the last thing it writes there, never followed by a bar that another
/// thread was drawing when the signal came.
void writeProgressText(const std::string& text);

/// Removes every staged output, stops the guarded children, prints the
/// interruption line and ends the process by `signal`, as
/// removeStagedOutputsOnTerminationSignals() does. For a program whose
/// child process was ended by a termination signal sent to the child
/// alone: it ends the same way.
[[noreturn]] void endBySignal(int signal);

}  // namespace stvd::files
