// Starting the tool's child processes (see child_process.hpp).
#include "child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "command_line.hpp"

namespace stvd::tool {
namespace {

/// `program` itself when it names a path, else the first executable file
/// of that name in an absolute folder of PATH (looked up here: between fork
/// and exec only async-signal-safe calls are allowed). Empty and relative
/// entries of PATH, which execvp takes as the working folder or folders in
/// it, are skipped: a program planted there never runs.
std::string executablePath(const std::string& program) {
  if (program.find('/') != std::string::npos) return program;
  const char* path = std::getenv("PATH");
  const std::string folders = path && *path ? path : "/usr/local/bin:/usr/bin:/bin";
  for (std::size_t start = 0; start <= folders.size();) {
    std::size_t end = folders.find(':', start);
    if (end == std::string::npos) end = folders.size();
    const std::string folder = folders.substr(start, end - start);
    start = end + 1;
    if (folder.empty() || folder[0] != '/') continue;
    const std::string candidate = folder + "/" + program;
    struct stat status {};
    if (::stat(candidate.c_str(), &status) == 0 && S_ISREG(status.st_mode) && ::access(candidate.c_str(), X_OK) == 0)
      return candidate;
  }
  return program;  // exec fails with ENOENT, which is reported
}

// Runs the module given by the two arguments after it, the folder that holds
// the package stvd first on sys.path (none when empty), as `python -m` would.
const char* kPythonBootstrap =
    "import runpy, sys\n"
    "folder, module = sys.argv[1:3]\n"
    "del sys.argv[1:3]\n"
    "if folder:\n"
    "    sys.path.insert(0, folder)\n"
    "runpy.run_module(module, run_name='__main__', alter_sys=True)\n";

}  // namespace

void prepareSignalsForExec(bool parentDeath) {
  sigset_t termination, none;
  files::handledTerminationSignals(termination);
  for (int s = 1; s < NSIG; ++s)
    if (sigismember(&termination, s) == 1) ::signal(s, SIG_DFL);
  sigemptyset(&none);
  ::pthread_sigmask(SIG_SETMASK, &none, nullptr);
  if (parentDeath) ::prctl(PR_SET_PDEATHSIG, SIGTERM);
}

ChildProcess::ChildProcess(const std::string& program, const std::vector<std::string>& arguments,
                           const std::vector<std::string>& environment, ChildStreams streams) {
  const std::string executable = executablePath(program);
  std::vector<std::string> args = arguments, env = environment;
  std::vector<char*> argv, envp;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  for (std::string& e : env) envp.push_back(e.data());
  envp.push_back(nullptr);
  // The child says why exec failed through this pipe (closed unread by a
  // successful exec).
  int failure[2];
  if (::pipe2(failure, O_CLOEXEC) != 0)
    throw ToolError(kExitInternal, "cannot make a pipe: " + std::string(std::strerror(errno)));
  const pid_t parent = ::getpid();
  int error = 0;
  guard_ = std::make_unique<files::ChildProcessGuard>([&]() -> pid_t {
    const pid_t child = ::fork();
    if (child == 0) {
      prepareSignalsForExec(/*parentDeath=*/true);
      // The tool died between fork and prctl: nobody would stop this child.
      if (::getppid() != parent) ::_exit(127);
      if (streams.input >= 0) ::dup2(streams.input, STDIN_FILENO);
      if (streams.errors >= 0) ::dup2(streams.errors, STDERR_FILENO);
      ::execve(executable.c_str(), argv.data(), envp.data());
      const int reason = errno;
      (void)!::write(failure[1], &reason, sizeof reason);
      ::_exit(127);
    }
    if (child < 0) {
      const int reason = errno;
      ::close(failure[0]);
      ::close(failure[1]);
      throw ToolError(kExitInternal, "cannot run " + program + ": " + std::strerror(reason));
    }
    return child;
  });
  pid_ = guard_->pid();
  ::close(failure[1]);
  ssize_t n;
  while ((n = ::read(failure[0], &error, sizeof error)) < 0 && errno == EINTR) {
  }
  ::close(failure[0]);
  if (n == static_cast<ssize_t>(sizeof error)) {
    wait();
    throw ToolError(kExitInternal, "cannot run " + program + ": " + std::strerror(error));
  }
}

int ChildProcess::wait() {
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0) {
    if (errno != EINTR) throw ToolError(kExitInternal, "lost the child process: " + std::string(std::strerror(errno)));
  }
  guard_.reset();  // reaped: its id may be another process's now
  return status;
}

std::vector<std::string> isolatedPythonCommand(const std::string& interpreter, const std::string& packageFolder,
                                               const std::string& module,
                                               const std::vector<std::string>& arguments) {
  std::vector<std::string> command{interpreter, "-I", "-c", kPythonBootstrap, packageFolder, module};
  command.insert(command.end(), arguments.begin(), arguments.end());
  return command;
}

}  // namespace stvd::tool
