// `stvd report` and the --report option of distance, path and connectivity.
// The page is drawn by the Python package (stvd.report, with matplotlib),
// which the tool runs as a child process: `python3 -m stvd.report ...` with
// the interpreter the package was built for, the package found next to this
// executable (docs/report.md).
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace stvd::tool {

/// `stvd report ARGS`: runs stvd.report with ARGS; returns its exit code.
int runReport(int argc, char** argv);

/// A report asked for with --report FILE.html, an output of the run that the
/// command declares in its RunFiles like every other (never an input, never
/// another output). start() starts checking, in the background while the
/// run computes, that Python can draw; requireReady() waits for that check
/// (call it before writing any output, so that a missing package stops the
/// run with nothing written); write() draws the page from the run's files,
/// and stvd.report writes it atomically.
class ReportRequest {
 public:
  ReportRequest() = default;
  ReportRequest(const ReportRequest&) = delete;
  ReportRequest& operator=(const ReportRequest&) = delete;
  ~ReportRequest();

  /// Nothing when `path` is empty. Throws ToolError (usage) when it is not
  /// .html.
  void start(const std::string& path);
  bool requested() const { return !path_.empty(); }
  const std::string& path() const { return path_; }
  void requireReady();
  /// Runs stvd.report with `arguments` and -o PATH (-q when `quiet`);
  /// ToolError with the child's message and exit code when it fails.
  void write(std::vector<std::string> arguments, bool quiet);

 private:
  std::string path_;
  pid_t check_ = -1;
  int checkErrors_ = -1;  // read end of the check's stderr
};

/// A private folder in the system's temporary folder for the files a
/// report reads (a distance map the run did not write, its statistics),
/// removed with everything in it when it goes out of scope.
class ScratchFolder {
 public:
  ScratchFolder();
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  ~ScratchFolder();
  std::string file(const std::string& name) const { return path_ + "/" + name; }

 private:
  std::string path_;
};

}  // namespace stvd::tool
