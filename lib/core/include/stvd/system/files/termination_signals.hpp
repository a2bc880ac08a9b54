// What a program does when it is told to stop (SIGINT from Ctrl-C, SIGTERM
// from a job scheduler, SIGHUP when its terminal goes away): remove every
// output it has staged but not committed, stop the child processes it runs,
// and end by the same signal, so that a shell reports 128 + the signal
// number (130, 143, 129) and a script loop around it stops as well.
#pragma once

#include <sys/types.h>

#include <string>

namespace stvd::files {

/// Blocks SIGINT, SIGTERM and SIGHUP in the calling thread and in every
/// thread it creates afterwards, and starts a thread that waits for them
/// (sigwait). Call it first in main(), before any other thread exists.
/// Signals whose disposition is "ignore" when it is called (a program
/// started in the background by a non-interactive shell ignores SIGINT)
/// stay ignored. On a signal the thread waits for a commit in progress to
/// finish, then sends the signal to the registered child processes and
/// waits for them to end, removes the staging folders of every
/// OutputTransaction, prints "<programName>: interrupted (SIGINT)" on
/// stderr (unless `programName` is empty or a child process ran, which
/// reports it itself) and ends the process by the signal.
/// Calling it again does nothing.
void removeStagedOutputsOnTerminationSignals(const std::string& programName);

/// The signals removeStagedOutputsOnTerminationSignals() handles (empty
/// before it is called): a child process should start with them unblocked
/// and at their default action (posix_spawnattr_setsigmask, setsigdefault),
/// so that it can handle them itself.
void handledTerminationSignals(sigset_t& signals);

/// While it lives, the child process `child` is sent the termination
/// signal the program receives, and waited for, before the program ends.
class ChildProcessGuard {
 public:
  explicit ChildProcessGuard(pid_t child);
  ~ChildProcessGuard();
  ChildProcessGuard(const ChildProcessGuard&) = delete;
  ChildProcessGuard& operator=(const ChildProcessGuard&) = delete;

 private:
  pid_t child_;
};

/// Removes every staged output, then ends the process by `signal` as
/// removeStagedOutputsOnTerminationSignals() does, without a message. For a
/// program whose child process was ended by a termination signal (and has
/// reported it): it ends the same way.
[[noreturn]] void endBySignal(int signal);

}  // namespace stvd::files
