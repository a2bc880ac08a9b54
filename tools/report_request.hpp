// `stvd report` and the --report option of distance, path and connectivity.
// The page is drawn by the Python package (stvd.report, with matplotlib),
// which the tool runs as a child process: `python3 -I` running stvd.report
// with the interpreter the package was built for, the package found next
// to this executable (child_process.hpp; docs/report.md).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "child_process.hpp"

namespace stvd::tool {

/// `stvd report ARGS`: runs stvd.report with ARGS; returns its exit code.
int runReport(int argc, char** argv);

/// A report asked for with --report FILE.html, an output of the run that the
/// command declares in its RunFiles like every other (never an input, never
/// another output). start() starts stvd.report --prepare (isolated),
/// which while the run computes checks that it can draw and does the
/// imports and the first drawing that every page costs, then waits for the
/// page's arguments on its stdin; requireReady() waits until it says so
/// (call it before writing any output, so that a missing package stops the
/// run with nothing written); write() hands it the run's files, and it draws
/// the page and writes it atomically. A run that stops ends the child.
class ReportRequest {
 public:
  ReportRequest() = default;
  ReportRequest(const ReportRequest&) = delete;
  ReportRequest& operator=(const ReportRequest&) = delete;
  ~ReportRequest();

  /// Nothing when `path` is empty. Throws ToolError (usage) when it is not
  /// .html, or when a `subject` (--subject, the page's name) comes without
  /// a page.
  void start(const std::string& path, const std::string& subject = "");
  bool requested() const { return !path_.empty(); }
  const std::string& path() const { return path_; }
  void requireReady();
  /// Runs stvd.report with `arguments` and -o PATH (-q when `quiet`);
  /// ToolError with the child's message and exit code when it fails.
  void write(std::vector<std::string> arguments, bool quiet);

 private:
  std::string path_;
  std::string subject_;  // empty: the page is named after the input
  std::unique_ptr<ChildProcess> child_;  // stvd.report --prepare, started by start()
  int errors_ = -1;     // read end of its stderr
  int arguments_ = -1;  // write end of its stdin: the page's arguments
  bool ready_ = false;
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
  /// The statistics file a report reads: `statsPath` when the run wrote
  /// one to a file, otherwise (none, or a stream such as /dev/stdout) `json`
  /// written here as run.json.
  std::string statisticsFile(const std::string& statsPath, const std::string& json) const;

 private:
  std::string path_;
};

}  // namespace stvd::tool
