// The subcommands of `stvd`. Each takes the whole argv (argv[1] is the
// subcommand's name), returns an exit code and throws ToolError on failure.
#pragma once

namespace stvd::tool {

int runDistance(int argc, char** argv);
int runInfo(int argc, char** argv);
int runPath(int argc, char** argv);
int runConnectivity(int argc, char** argv);
/// `stvd cohort`: replaces the process with the Python package's cohort runner.
int runCohort(int argc, char** argv);

}  // namespace stvd::tool
