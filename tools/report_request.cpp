// Running stvd.report of the Python package (see report_request.hpp).
#include "report_request.hpp"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>

#include "command_line.hpp"

extern char** environ;

namespace stvd::tool {
namespace {

#ifdef STVD_PYTHON_EXECUTABLE
/// The folder that holds the package stvd (pythonPackageFolder), or an
/// error saying where it was looked for.
std::string packageFolder() {
  if (std::string folder = pythonPackageFolder("report.py"); !folder.empty()) return folder;
  const std::string here = executableFolder();
  throw ToolError(kExitInternal, "report: the Python package stvd is not next to this stvd (looked in " + here +
                                     "/../python and " + here + "/../" STVD_PYTHON_INSTALL_DIR +
                                     "); build the target stvd_python or install stvd");
}
#endif

std::string interpreter() {
  const char* given = std::getenv("STVD_PYTHON");
  if (given && *given) return given;
#ifdef STVD_PYTHON_EXECUTABLE
  return STVD_PYTHON_EXECUTABLE;
#else
  throw ToolError(kExitInternal,
                  "report: this stvd was built without the Python package (STVD_WITH_PYTHON), which draws reports");
#endif
}

/// Starts python -m stvd.report ARGS with the package on PYTHONPATH; the
/// child's stderr goes to a pipe whose read end is returned in `errors`.
pid_t spawnReport(const std::vector<std::string>& arguments, int& errors) {
  const std::string python = interpreter();
#ifdef STVD_PYTHON_EXECUTABLE
  std::string pythonPath = packageFolder();
#else
  std::string pythonPath;
#endif
  if (const char* old = std::getenv("PYTHONPATH"); old && *old) pythonPath += ":" + std::string(old);
  std::vector<std::string> environment{"PYTHONPATH=" + pythonPath, "MPLBACKEND=Agg"};
  for (char** e = environ; *e; ++e)
    if (std::strncmp(*e, "PYTHONPATH=", 11) != 0 && std::strncmp(*e, "MPLBACKEND=", 11) != 0)
      environment.emplace_back(*e);
  std::vector<std::string> args{python, "-m", "stvd.report"};
  args.insert(args.end(), arguments.begin(), arguments.end());
  std::vector<char*> argv, envp;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  for (std::string& e : environment) envp.push_back(e.data());
  envp.push_back(nullptr);

  int pipeEnds[2];
  if (::pipe2(pipeEnds, O_CLOEXEC) != 0)
    throw ToolError(kExitInternal, "report: cannot make a pipe: " + std::string(std::strerror(errno)));
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, pipeEnds[1], STDERR_FILENO);
  pid_t child = -1;
  const int spawned = ::posix_spawnp(&child, python.c_str(), &actions, nullptr, argv.data(), envp.data());
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipeEnds[1]);
  if (spawned != 0) {
    ::close(pipeEnds[0]);
    throw ToolError(kExitInternal, "report: cannot run " + python + " (Python 3 with matplotlib draws reports): " +
                                       std::strerror(spawned));
  }
  errors = pipeEnds[0];
  return child;
}

/// Waits for the child; ToolError with its last stderr line and exit code
/// when it failed.
void finish(pid_t child, int errors) {
  std::string text;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(errors, buffer, sizeof buffer);
    if (n > 0) {
      text.append(buffer, static_cast<std::size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  ::close(errors);
  int status = 0;
  while (::waitpid(child, &status, 0) < 0)
    if (errno != EINTR) throw ToolError(kExitInternal, "report: lost the child process");
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return;
  while (!text.empty() && (text.back() == '\n' || text.back() == '\r')) text.pop_back();
  std::string line = text.substr(text.find_last_of('\n') == std::string::npos ? 0 : text.find_last_of('\n') + 1);
  if (line.rfind("stvd: ", 0) == 0) line = line.substr(6);
  if (line.empty()) line = "report: the Python report ended without a message";
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : kExitInternal;
  throw ToolError(code == kExitOk ? kExitInternal : code, line);
}

}  // namespace

int runReport(int argc, char** argv) {
  std::vector<std::string> arguments(argv + 2, argv + argc);
  int errors = -1;
  const pid_t child = spawnReport(arguments, errors);
  finish(child, errors);
  return kExitOk;
}

ReportRequest::~ReportRequest() {
  if (check_ > 0) {
    ::kill(check_, SIGTERM);
    ::close(checkErrors_);
    int status = 0;
    ::waitpid(check_, &status, 0);
  }
}

void ReportRequest::start(const std::string& path) {
  path_ = path;
  if (path.empty()) return;
  const std::string extension = std::filesystem::path(path).extension().string();
  if (extension != ".html" && extension != ".htm") usageError(path + ": --report writes an .html page");
  check_ = spawnReport({"--check"}, checkErrors_);
}

void ReportRequest::requireReady() {
  if (check_ <= 0) return;
  const pid_t child = check_;
  check_ = -1;
  finish(child, checkErrors_);
}

void ReportRequest::write(std::vector<std::string> arguments, bool quiet) {
  requireReady();
  arguments.insert(arguments.end(), {"-o", path_});
  if (quiet) arguments.push_back("-q");
  int errors = -1;
  const pid_t child = spawnReport(arguments, errors);
  finish(child, errors);
}

ScratchFolder::ScratchFolder() {
  std::string pattern = (std::filesystem::temp_directory_path() / "stvd-report-XXXXXX").string();
  if (!::mkdtemp(pattern.data()))
    throw ToolError(kExitOutput, "report: cannot make a temporary folder: " + std::string(std::strerror(errno)));
  path_ = pattern;
}

ScratchFolder::~ScratchFolder() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace stvd::tool
