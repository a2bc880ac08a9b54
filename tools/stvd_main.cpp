// `stvd`: the command-line tool. Dispatches to a subcommand and turns every
// failure into one line on stderr and a documented exit code.
#include <exception>
#include <iostream>
#include <string>

#include "command_line.hpp"
#include "stvd/system/files/termination_signals.hpp"
#include "stvd/errors.hpp"
#include "stvd/itk/itk_messages.hpp"
#include "option_help.hpp"
#include "report_request.hpp"
#include "subcommands.hpp"
#include "tet_mesh_commands.hpp"

namespace {

const char* kToolHelp =
    "Usage: stvd COMMAND [options]\n"
    "\n"
    "Anisotropic geodesic distances on diffusion tensor images (stvd " STVD_VERSION_TEXT ").\n"
    "\n"
    "Commands:\n"
    "  distance INPUT -o OUTPUT [options]   distance map (mm) from seeds over a tensor volume\n"
    "  path INPUT -o PATHS [options]        geodesic paths from targets to the seeds as .tck, .trk\n"
    "                                       or .vtk streamlines with a TSV summary (docs/paths.md)\n"
    "  connectivity INPUT --labels L -o T   geodesic distance and connectivity index between\n"
    "                                       every pair of labelled regions, as a TSV table\n"
    "  cohort MANIFEST.tsv -o OUTDIR        every subject of a manifest (connectivity, distance\n"
    "                                       maps) on a Dask cluster, resumable (docs/cohorts.md)\n"
    "  info INPUT [options]                 geometry, layout, order, frame and eigenvalue\n"
    "                                       statistics of a tensor volume\n"
    "  report --stats RUN.json -o R.html    a self-contained HTML QC page of a run (also\n"
    "                                       --report R.html on distance, path, connectivity)\n"
    "  tetrahedralize SURFACE -o MESH       quality tet mesh of a closed surface (TetGen); then\n"
    "                                       `stvd distance MESH.node` (docs/tet_meshes.md)\n"
    "  help [COMMAND]                       this text, or a command's (also COMMAND --help)\n"
    "\n"
    "Inputs: NIfTI (.nii, .nii.gz), NRRD (.nrrd, .nhdr) and MRtrix (.mif, .mif.gz, .mih) tensor\n"
    "volumes; outputs: float32 NIfTI, NRRD or MRtrix on the input's grid. Coordinates are\n"
    "millimetres; seed points are RAS unless --lps is given; voxel indices are 0-based, in the\n"
    "file's axis order (MRtrix may show other indices: stvd info --voxel). See docs/cli.md.\n"
    "\n"
    "Exit codes: 0 success; 1 internal error; 2 bad command line; 3 unreadable or unusable\n"
    "input; 4 nothing to compute (empty domain, seed outside the image or domain); 5 output\n"
    "cannot be written; 6 not enough memory for the run.\n";

int dispatch(int argc, char** argv) {
  using namespace stvd::tool;
  if (argc < 2) {
    std::cerr << kToolHelp;
    return kExitUsage;
  }
  const std::string command = argv[1];
  if (command == "distance") return runDistance(argc, argv);
  if (command == "info") return runInfo(argc, argv);
  if (command == "tetrahedralize") return runTetrahedralize(argc, argv);
  if (command == "path") return runPath(argc, argv);
  if (command == "connectivity") return runConnectivity(argc, argv);
  if (command == "cohort") return runCohort(argc, argv);
  if (command == "report") return runReport(argc, argv);
  if (command == "-h" || command == "--help" || command == "help") {
    // Hidden: docs/cli.md's option tables (scripts/update_cli_docs.py).
    if (command == "help" && argc > 2 && std::string(argv[2]) == "--markdown") return printOptionTables(argc, argv, 3);
    if (command == "help" && argc > 2) {
      char* helpArgv[] = {argv[0], argv[2], const_cast<char*>("--help")};
      return dispatch(3, helpArgv);
    }
    std::cout << kToolHelp;
    return kExitOk;
  }
  if (command == "--version") {
    std::cout << "stvd " STVD_VERSION_TEXT "\n";
    return kExitOk;
  }
  usageError("unknown command '" + command +
             "' (commands: distance, path, connectivity, cohort, report, info, tetrahedralize; see stvd --help)");
}

/// The exit code of each kind of the library's errors (stvd/errors.hpp): the
/// one place where they meet the codes of --help and docs/cli.md. Reading
/// an image that fails is kExitInput; a failed output never gets here as an
/// imaging::ImageIoError, since every output is written where its failure
/// becomes kExitOutput.
int exitCodeOf(stvd::ErrorKind kind) {
  using namespace stvd::tool;
  switch (kind) {
    case stvd::ErrorKind::Option: return kExitUsage;
    case stvd::ErrorKind::Input: return kExitInput;
    case stvd::ErrorKind::NothingToCompute: return kExitDomain;
    case stvd::ErrorKind::Output: return kExitOutput;
  }
  return kExitInternal;
}

}  // namespace

int main(int argc, char** argv) {
  using namespace stvd::tool;
  // Before any other thread exists: Ctrl-C, SIGTERM and SIGHUP remove the
  // outputs staged so far and end the tool by the signal.
  stvd::files::removeStagedOutputsOnTerminationSignals("stvd");
  // The tool owns its process: ITK's own messages during our reads and
  // writes stay off the terminal (each problem is one line of ours).
  stvd::imaging::installItkMessageFilter();
  try {
    return dispatch(argc, argv);
  } catch (const ToolError& e) {
    if (e.exitCode() != kExitOk) std::cerr << "stvd: " << e.what() << std::endl;
    return e.exitCode();
  } catch (const stvd::Error& e) {  // options, inputs, files: one line and the kind's exit code
    std::cerr << "stvd: " << e.what() << std::endl;
    return exitCodeOf(e.kind());
  } catch (const std::bad_alloc&) {
    std::cerr << "stvd: out of memory (the machine, its control group or ulimit -v allows less than the run "
                 "needs)"
              << std::endl;
    return kExitMemory;
  } catch (const std::exception& e) {
    std::cerr << "stvd: internal error: " << e.what() << std::endl;
    return kExitInternal;
  }
}
