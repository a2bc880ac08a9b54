// `stvd cohort`: runs the cohort layer of the Python package (stvd.cohort,
// on Dask) in place of this process. The work of each subject is the
// library's, called through the package; the scheduling, the manifest and
// the per-subject files are Python's, where Dask is.
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "command_line.hpp"
#include "subcommands.hpp"

namespace stvd::tool {

int runCohort(int argc, char** argv) {
#ifndef STVD_PYTHON_EXECUTABLE
  (void)argc;
  (void)argv;
  throw ToolError(kExitInternal,
                  "cohort: this stvd was built without its Python package (STVD_WITH_PYTHON), which runs cohorts");
#else
  // Without the package next to the tool, the interpreter's own (pip).
  const std::string folder = pythonPackageFolder("cohort.py");
  if (!folder.empty()) {
    const char* path = std::getenv("PYTHONPATH");
    const std::string value = folder + (path && *path ? ":" + std::string(path) : std::string());
    ::setenv("PYTHONPATH", value.c_str(), 1);
  }
  std::vector<char*> pythonArgv{const_cast<char*>(STVD_PYTHON_EXECUTABLE), const_cast<char*>("-m"),
                                const_cast<char*>("stvd.cohort")};
  for (int i = 2; i < argc; ++i) pythonArgv.push_back(argv[i]);
  pythonArgv.push_back(nullptr);
  // The interpreter takes this process over: its exit code, signals and
  // terminal are the command's.
  ::execv(STVD_PYTHON_EXECUTABLE, pythonArgv.data());
  throw ToolError(kExitInternal, std::string("cohort: cannot run ") + STVD_PYTHON_EXECUTABLE + ": " +
                                     std::strerror(errno));
#endif
}

}  // namespace stvd::tool
