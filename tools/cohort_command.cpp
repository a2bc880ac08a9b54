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

#include "child_process.hpp"
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
  // Isolated (child_process.hpp): nothing planted in the working folder,
  // the manifest's folder or OUTDIR, the user's site packages or PYTHON*
  // variables runs, here or in the Dask workers (which inherit -I).
  std::vector<std::string> command = isolatedPythonCommand(
      STVD_PYTHON_EXECUTABLE, pythonPackageFolder("cohort.py"), "stvd.cohort",
      std::vector<std::string>(argv + 2, argv + argc));
  std::vector<char*> pythonArgv;
  for (std::string& word : command) pythonArgv.push_back(word.data());
  pythonArgv.push_back(nullptr);
  // The interpreter takes this process over: its exit code, signals and
  // terminal are the command's. The signals this process blocked for its
  // signal thread are unblocked first (a blocked mask survives exec, and
  // the interpreter and its Dask workers would never see Ctrl-C or
  // SIGTERM); one that arrives meanwhile ends it by its default action.
  prepareSignalsForExec(/*parentDeath=*/false);
  ::execv(STVD_PYTHON_EXECUTABLE, pythonArgv.data());
  throw ToolError(kExitInternal, std::string("cohort: cannot run ") + STVD_PYTHON_EXECUTABLE + ": " +
                                     std::strerror(errno));
#endif
}

}  // namespace stvd::tool
