// Running stvd.report of the Python package (see report_request.hpp).
#include "report_request.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>

#include "child_process.hpp"
#include "command_line.hpp"
#include "stvd/system/files/file_contents.hpp"
#include "stvd/system/files/output_destination.hpp"

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

/// Starts stvd.report with ARGS (child_process.hpp: isolated, default
/// signal mask, stopped with the tool); the child's stderr goes to a pipe
/// whose read end is returned in `errors`. With `input`, its stdin is a
/// pipe too, whose write end is returned there.
std::unique_ptr<ChildProcess> spawnReport(const std::vector<std::string>& arguments, int& errors,
                                          int* input = nullptr) {
  const std::string python = interpreter();
#ifdef STVD_PYTHON_EXECUTABLE
  const std::string folder = packageFolder();
#else
  const std::string folder;
#endif
  std::vector<std::string> environment{"MPLBACKEND=Agg"};
  for (char** e = environ; *e; ++e)
    if (std::strncmp(*e, "MPLBACKEND=", 11) != 0) environment.emplace_back(*e);

  int pipeEnds[2], inputEnds[2] = {-1, -1};
  if (::pipe2(pipeEnds, O_CLOEXEC) != 0 || (input && ::pipe2(inputEnds, O_CLOEXEC) != 0))
    throw ToolError(kExitInternal, "report: cannot make a pipe: " + std::string(std::strerror(errno)));
  std::unique_ptr<ChildProcess> child;
  try {
    child = std::make_unique<ChildProcess>(python, isolatedPythonCommand(python, folder, "stvd.report", arguments),
                                           environment, ChildStreams{inputEnds[0], pipeEnds[1]});
  } catch (const ToolError& e) {
    for (const int fd : {pipeEnds[0], pipeEnds[1], inputEnds[0], inputEnds[1]})
      if (fd >= 0) ::close(fd);
    throw ToolError(kExitInternal, std::string("report: ") + e.what() + " (Python 3 with matplotlib draws reports)");
  }
  ::close(pipeEnds[1]);
  if (input) ::close(inputEnds[0]);
  errors = pipeEnds[0];
  if (input) *input = inputEnds[1];
  return child;
}

/// Reads one line of the child's stderr (byte by byte, so that nothing
/// after it is taken from the pipe) into `text`; nothing at its end.
void readLine(int errors, std::string& text) {
  char c = 0;
  for (;;) {
    const ssize_t n = ::read(errors, &c, 1);
    if (n == 1) {
      text += c;
      if (c == '\n') return;
    } else if (n == 0 || errno != EINTR) {
      return;
    }
  }
}

/// Waits for the child; ToolError with its last stderr line (`text` holds
/// what was read of it already) and exit code when it failed.
void finish(ChildProcess& child, int errors, std::string text = "") {
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
  const int status = child.wait();
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
  const std::unique_ptr<ChildProcess> child = spawnReport(arguments, errors);
  finish(*child, errors);
  return kExitOk;
}

ReportRequest::~ReportRequest() {
  if (child_) {  // the run stopped: the child is told so (no arguments) and ended
    ::close(arguments_);
    ::kill(child_->pid(), SIGTERM);
    ::close(errors_);
    try {
      child_->wait();
    } catch (const ToolError&) {  // nothing to wait for
    }
  }
}

void ReportRequest::start(const std::string& path, const std::string& subject) {
  path_ = path;
  subject_ = subject;
  if (path.empty()) {
    if (!subject.empty()) usageError("--subject names the QC page: add --report FILE.html");
    return;
  }
  const std::string extension = std::filesystem::path(path).extension().string();
  if (extension != ".html" && extension != ".htm") usageError(path + ": --report writes an .html page");
  child_ = spawnReport({"--prepare"}, errors_, &arguments_);
}

void ReportRequest::requireReady() {
  if (!child_ || ready_) return;
  // Lines before "ready" are what the imports said (matplotlib's first run
  // builds its font cache and says so): shown only when the child fails.
  std::string text;
  for (;;) {
    std::string line;
    readLine(errors_, line);
    if (line == "ready\n") {
      ready_ = true;
      return;
    }
    if (line.empty()) break;  // the child ended
    text += line;
  }
  // It could not draw: its message, and its exit code.
  const std::unique_ptr<ChildProcess> child = std::move(child_);
  ::close(arguments_);
  finish(*child, errors_, text);
  throw ToolError(kExitInternal, "report: the Python report stopped before it was ready");
}

void ReportRequest::write(std::vector<std::string> arguments, bool quiet) {
  requireReady();
  arguments.insert(arguments.end(), {"-o", path_});
  // One word, so that a name starting with '-' is not taken for an option.
  if (!subject_.empty()) arguments.push_back("--subject=" + subject_);
  if (quiet) arguments.push_back("-q");
  std::string text;
  for (const std::string& a : arguments) text += a + '\0';
  // A child that died would turn the write into SIGPIPE: EPIPE instead,
  // and its own message from finish().
  struct sigaction ignore {}, previous {};
  ignore.sa_handler = SIG_IGN;
  ::sigaction(SIGPIPE, &ignore, &previous);
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(arguments_, text.data() + done, text.size() - done);
    if (n > 0)
      done += static_cast<std::size_t>(n);
    else if (errno != EINTR)
      break;
  }
  ::sigaction(SIGPIPE, &previous, nullptr);
  ::close(arguments_);
  const std::unique_ptr<ChildProcess> child = std::move(child_);
  finish(*child, errors_);
}

ScratchFolder::ScratchFolder() {
  std::string pattern = (std::filesystem::temp_directory_path() / "stvd-report-XXXXXX").string();
  if (!::mkdtemp(pattern.data()))
    throw ToolError(kExitOutput, "report: cannot make a temporary folder: " + std::string(std::strerror(errno)));
  path_ = pattern;
}

std::string ScratchFolder::statisticsFile(const std::string& statsPath, const std::string& json) const {
  // A statistics "file" that is a stream (/dev/stdout, a FIFO) cannot be
  // read back: the report gets a copy.
  if (!statsPath.empty() && !files::isStreamOutput(statsPath)) return statsPath;
  try {
    files::writeFileContents(file("run.json"), json);
  } catch (const std::runtime_error& e) {
    throw ToolError(kExitOutput, e.what());
  }
  return file("run.json");
}

ScratchFolder::~ScratchFolder() {
  std::error_code ignored;
  std::filesystem::remove_all(path_, ignored);
}

}  // namespace stvd::tool
