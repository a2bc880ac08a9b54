#include "stvd/system/files/termination_signals.hpp"

#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <sys/signalfd.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <filesystem>
#include <mutex>
#include <thread>

#include "process_registry.hpp"

namespace stvd::files {
namespace {

const int kTerminationSignals[] = {SIGINT, SIGTERM, SIGHUP};

std::string& programNameForMessages() {
  static std::string name;
  return name;
}

/// A duplicate of standard error made when the handling is installed: code
/// that diverts standard error for a while (a host program may) must not
/// swallow the line that says the run was interrupted.
int& messageDescriptor() {
  static int fd = STDERR_FILENO;
  return fd;
}

/// Held by a thread writing progress text on stderr, and from the
/// interruption line to the end by the thread that ends the process.
std::mutex& progressTextMutex() {
  static std::mutex mutex;
  return mutex;
}

/// The signals the waiting thread handles (blocked in every thread).
sigset_t& handledSignals() {
  static sigset_t handled = [] {
    sigset_t none;
    sigemptyset(&none);
    return none;
  }();
  return handled;
}

/// The termination signal the waiting thread has seen arrive (0 before).
/// Set before the signal leaves the pending set, so that a commit that
/// looks for a signal always finds it in one of the two.
std::atomic<int>& arrivedSignal() {
  static std::atomic<int> signal{0};
  return signal;
}

/// A handled signal pending for the process (blocked everywhere but not yet
/// taken by the waiting thread), or 0.
int pendingHandledSignal() {
  sigset_t pending;
  sigemptyset(&pending);
  if (::sigpending(&pending) != 0) return 0;
  const sigset_t handled = handledSignals();
  for (const int s : kTerminationSignals)
    if (sigismember(&handled, s) == 1 && sigismember(&pending, s) == 1) return s;
  return 0;
}

/// Waits for a handled signal and returns it. The signal is recorded in
/// arrivedSignal() while it is still pending and only then taken: a thread
/// that asks terminationSignalArrived() between the two never misses it.
int waitForTerminationSignal(const sigset_t& handled) {
  const int fd = ::signalfd(-1, &handled, SFD_CLOEXEC);
  if (fd >= 0) {
    for (;;) {
      pollfd ready{fd, POLLIN, 0};
      if (::poll(&ready, 1, -1) <= 0) continue;  // EINTR
      const int signal = pendingHandledSignal();
      if (signal == 0) continue;
      arrivedSignal().store(signal);
      signalfd_siginfo taken{};
      (void)!::read(fd, &taken, sizeof taken);  // a second signal meanwhile counts as a second one
      return signal;
    }
  }
  // Without signalfd (it cannot fail for want of anything but descriptors):
  // sigwait, which takes the signal before it can be recorded.
  int signal = 0;
  while (::sigwait(&handled, &signal) != 0) {
  }
  arrivedSignal().store(signal);
  return signal;
}

/// With the registry locked: the children are told to stop and waited for
/// (without reaping them: the thread that started a child still owns it),
/// and the staging folders are removed. A child that takes its time (it
/// removes what it staged, or finishes a commit) is waited for; a second
/// termination signal meanwhile kills it at once.
void cleanUp(detail::ProcessRegistry& registry, int signal) {
  for (const pid_t child : registry.children) ::kill(child, signal);
  const sigset_t handled = handledSignals();
  for (const pid_t child : registry.children) {
    for (;;) {
      siginfo_t info{};
      if (::waitid(P_PID, static_cast<id_t>(child), &info, WEXITED | WNOWAIT | WNOHANG) != 0) {
        if (errno == EINTR) continue;
        break;  // reaped by its owner meanwhile
      }
      if (info.si_pid == child) break;  // ended
      const timespec tick{0, 20'000'000};
      if (::sigtimedwait(&handled, nullptr, &tick) > 0)
        for (const pid_t c : registry.children) ::kill(c, SIGKILL);
    }
  }
  for (const std::string& folder : registry.stagingFolders) {
    std::error_code ec;
    std::filesystem::remove_all(folder, ec);
  }
  registry.stagingFolders.clear();
}

[[noreturn]] void endWithLockHeld(int signal, bool report) {
  // Held to the end: a progress bar drawn by another thread is either
  // written whole before the line or not at all (a bar written in pieces
  // around the line left "] 11% 1.0 s" after it).
  progressTextMutex().lock();
  const std::string& program = programNameForMessages();
  if (report && !program.empty()) {
    const char* name = signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : signal == SIGHUP ? "SIGHUP" : "signal";
    // On a terminal the line may follow a progress bar: it starts on a
    // cleared line.
    const int fd = messageDescriptor();
    const std::string clear = ::isatty(fd) ? "\r" + std::string(79, ' ') + "\r" : "";
    const std::string line = clear + program + ": interrupted (" + name + ")\n";
    (void)!::write(fd, line.data(), line.size());
  }
  // The signal's default action ends the process; the parent sees "killed
  // by the signal", which shells report as 128 + its number.
  ::signal(signal, SIG_DFL);
  sigset_t only;
  sigemptyset(&only);
  sigaddset(&only, signal);
  ::pthread_sigmask(SIG_UNBLOCK, &only, nullptr);
  ::raise(signal);
  ::_exit(128 + signal);  // not reached
}

}  // namespace

void handledTerminationSignals(sigset_t& signals) { signals = handledSignals(); }

void removeStagedOutputsOnTerminationSignals(const std::string& programName) {
  static std::once_flag once;
  std::call_once(once, [&] {
    programNameForMessages() = programName;
    const int duplicate = ::fcntl(STDERR_FILENO, F_DUPFD_CLOEXEC, 3);
    if (duplicate >= 0) messageDescriptor() = duplicate;
    sigset_t handled;
    sigemptyset(&handled);
    for (const int s : kTerminationSignals) {
      struct sigaction current {};
      if (::sigaction(s, nullptr, &current) == 0 && current.sa_handler == SIG_IGN) continue;
      sigaddset(&handled, s);
    }
    if (sigisemptyset(&handled)) return;
    handledSignals() = handled;
    ::pthread_sigmask(SIG_BLOCK, &handled, nullptr);
    std::thread([handled] {
      // Named, so that ps -L, a debugger and /proc/PID/task/*/comm show
      // that the process has taken charge of the signals (the tests wait
      // for it before they send one).
      ::pthread_setname_np(::pthread_self(), "stvd-signals");
      const int signal = waitForTerminationSignal(handled);
      detail::ProcessRegistry& registry = detail::processRegistry();
      registry.mutex.lock();  // held to the end: nothing is staged or committed meanwhile
      cleanUp(registry, signal);
      endWithLockHeld(signal, /*report=*/true);
    }).detach();
  });
}

int detail::terminationSignalArrived() {
  const int arrived = arrivedSignal().load();
  return arrived != 0 ? arrived : pendingHandledSignal();
}

void detail::endBySignalWithRegistryLocked(int signal) {
  cleanUp(processRegistry(), signal);
  endWithLockHeld(signal, /*report=*/true);
}

void writeProgressText(const std::string& text) {
  const std::lock_guard<std::mutex> lock(progressTextMutex());
  const char* data = text.data();
  std::size_t left = text.size();
  while (left > 0) {
    const ssize_t written = ::write(STDERR_FILENO, data, left);
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) return;  // a bar is not worth an error
    data += written;
    left -= static_cast<std::size_t>(written);
  }
}

void reportInterruptionsAs(const std::string& programName) {
  detail::ProcessRegistry& registry = detail::processRegistry();
  const std::lock_guard<std::mutex> lock(registry.mutex);  // the signal thread reads it with the lock held
  programNameForMessages() = programName;
}

void endBySignal(int signal) {
  detail::ProcessRegistry& registry = detail::processRegistry();
  registry.mutex.lock();  // held to the end: nothing is staged or committed meanwhile
  cleanUp(registry, signal);
  endWithLockHeld(signal, /*report=*/true);
}

ChildProcessGuard::ChildProcessGuard(pid_t child) : child_(child) {
  detail::ProcessRegistry& registry = detail::processRegistry();
  const std::lock_guard<std::mutex> lock(registry.mutex);
  if (child_ > 0) registry.children.push_back(child_);  // kill(-1) would reach every process
}

ChildProcessGuard::ChildProcessGuard(const std::function<pid_t()>& start) {
  detail::ProcessRegistry& registry = detail::processRegistry();
  const std::lock_guard<std::mutex> lock(registry.mutex);
  child_ = start();
  if (child_ > 0) registry.children.push_back(child_);
}

ChildProcessGuard::~ChildProcessGuard() {
  detail::ProcessRegistry& registry = detail::processRegistry();
  const std::lock_guard<std::mutex> lock(registry.mutex);
  auto& children = registry.children;
  children.erase(std::remove(children.begin(), children.end(), child_), children.end());
}

}  // namespace stvd::files
