// stvd-tetrahedralize: a quality tetrahedral mesh of a closed surface,
// written as TetGen .node/.ele/.face files. A program of its own because it
// links TetGen (AGPL-3.0-or-later) and because TetGen can crash on bad
// input: `stvd tetrahedralize` runs it as a child process and reports a
// crash as an error instead of dying with it.
#include <fcntl.h>
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "stvd/system/files/file_identity.hpp"
#include "stvd/system/files/output_transaction.hpp"
#include "stvd/system/files/termination_signals.hpp"
#include "stvd/tetgen/tetrahedralize.hpp"
#include "stvd/tetmesh/tet_mesh_writers.hpp"

namespace {

// The exit codes of the `stvd` tool (docs/cli.md).
constexpr int kExitOk = 0, kExitInternal = 1, kExitUsage = 2, kExitInput = 3, kExitOutput = 5;

const char* kHelp =
    "Usage: stvd-tetrahedralize SURFACE -o MESH [--max-volume V] [--quality Q] [--max-points N] [-q]\n"
    "\n"
    "Quality tetrahedral mesh of the interior of a closed surface (.off, .stl, .ply, .poly),\n"
    "through TetGen 1.5 (Hang Si; AGPL-3.0-or-later). Writes MESH.node, MESH.ele and MESH.face\n"
    "(0-based; MESH may also be given as MESH.node). Usually run as `stvd tetrahedralize`.\n"
    "\n"
    "  -o, --output MESH   base name of the output files (required); its folder must exist.\n"
    "  --max-volume V      upper bound on the volume of each tetrahedron (cubic units).\n"
    "  --quality Q         upper bound on the radius-edge ratio, >= 1.1 (default 2; 1.2 to 2).\n"
    "                      TetGen's refinement is proven to end for 2; below 1.1 it need not.\n"
    "  --max-points N      at most N points added to the surface's (default 2000000, about\n"
    "                      1.1 KB of memory each); a mesh that needs more is an error.\n"
    "  -q, --quiet         no summary on stdout.\n"
    "\n"
    "The surface is validated first (finite coordinates, non-degenerate polygons, closed).\n"
    "Exit codes: 0 success; 1 internal error; 2 bad command line; 3 invalid surface, or TetGen\n"
    "failed on it, or the mesh needs more than --max-points; 5 output cannot be written. No\n"
    "partial output is left behind.\n";

struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

double number(const std::string& option, const std::string& text) {
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') throw UsageError(option + ": '" + text + "' is not a number");
  return x;
}

/// The three files, staged together and moved into place at once (the .node
/// file, which names the mesh, last): a reader never sees a partial mesh,
/// and a failure leaves the files that were there before.
void writeMesh(const std::string& base, const stvd::tetmesh::TetMesh& mesh) {
  stvd::files::writeAtomically(base + ".node", [&](const std::string& stagingNode) {
    stvd::tetmesh::writeTetGenMesh(stvd::tetmesh::tetGenBaseName(stagingNode), mesh);
  });
}

/// The input surface and the file a .poly surface may take its points from.
std::vector<stvd::files::RunFile> inputFiles(const std::string& input) {
  std::vector<stvd::files::RunFile> files{{"input surface", input}};
  if (input.size() > 5 && input.compare(input.size() - 5, 5, ".poly") == 0)
    files.push_back({"points file of the input surface", input.substr(0, input.size() - 5) + ".node"});
  return files;
}

std::vector<stvd::files::RunFile> outputFiles(const std::string& base) {
  return {{".node file of the output mesh", base + ".node"},
          {".ele file of the output mesh", base + ".ele"},
          {".face file of the output mesh", base + ".face"}};
}

/// TetGen's loaders print progress and their own diagnostics on stdout; the
/// tool reports problems in one line of its own, so stdout is silenced
/// while they run.
stvd::tetgen::SurfaceMesh readSurfaceQuietly(const std::string& path) {
  std::fflush(stdout);
  const int saved = ::dup(STDOUT_FILENO);
  const int null = ::open("/dev/null", O_WRONLY);
  if (saved >= 0 && null >= 0) ::dup2(null, STDOUT_FILENO);
  if (null >= 0) ::close(null);
  auto restore = [&] {
    std::fflush(stdout);
    if (saved >= 0) {
      ::dup2(saved, STDOUT_FILENO);
      ::close(saved);
    }
  };
  try {
    stvd::tetgen::SurfaceMesh surface = stvd::tetgen::readSurface(path);
    restore();
    return surface;
  } catch (...) {
    restore();
    throw;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // `stvd tetrahedralize` runs this program with this first argument: it
  // reports an interruption itself, once this process has ended.
  const bool parentReports = argc > 1 && std::string(argv[1]) == "--interruptions-reported-by-parent";
  stvd::files::removeStagedOutputsOnTerminationSignals(parentReports ? "" : "stvd tetrahedralize");
  if (parentReports) {
    --argc;
    ++argv;
  }
  std::string input, output;
  stvd::tetgen::TetrahedralizeOptions options;
  bool quiet = false;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string a = argv[i];
      auto value = [&]() -> std::string {
        if (i + 1 >= argc) throw UsageError(a + " needs a value");
        return argv[++i];
      };
      if (a == "-h" || a == "--help") {
        std::cout << kHelp;
        return kExitOk;
      } else if (a == "-o" || a == "--output") {
        output = value();
      } else if (a == "--max-volume") {
        options.maxVolume = number(a, value());
        if (!(*options.maxVolume > 0.0)) throw UsageError("--max-volume must be positive");
      } else if (a == "--quality") {
        options.quality = number(a, value());
        if (!(options.quality >= stvd::tetgen::kMinimumQuality))
          throw UsageError("--quality must be at least 1.1 (below it TetGen's refinement need not end)");
      } else if (a == "--max-points") {
        const double n = number(a, value());
        if (!(n >= 1.0 && n <= 2147483647.0 && n == std::floor(n)))
          throw UsageError("--max-points must be a whole number from 1 to 2147483647");
        options.maxAddedPoints = static_cast<std::size_t>(n);
      } else if (a == "-q" || a == "--quiet") {
        quiet = true;
      } else if (!a.empty() && a[0] == '-') {
        throw UsageError("unknown option '" + a + "'");
      } else if (input.empty()) {
        input = a;
      } else {
        throw UsageError("more than one input ('" + input + "' and '" + a + "')");
      }
    }
    if (input.empty()) throw UsageError("no input surface (see --help)");
    if (output.empty()) throw UsageError("no output: -o MESH is required");
  } catch (const UsageError& e) {
    std::cerr << "stvd tetrahedralize: " << e.what() << std::endl;
    return kExitUsage;
  }
  const std::string base = stvd::tetmesh::tetGenBaseName(output);
  // An output that is the input, and an unwritable output folder, are found
  // before the meshing, not after it.
  try {
    stvd::files::checkOutputsAreNotInputs(inputFiles(input), outputFiles(base));
  } catch (const stvd::files::FileConflict& e) {
    std::cerr << "stvd tetrahedralize: " << e.what() << std::endl;
    return kExitUsage;
  }
  try {
    stvd::files::checkOutputPath(base + ".node");
  } catch (const stvd::files::OutputError& e) {
    std::cerr << "stvd tetrahedralize: " << e.what() << std::endl;
    return kExitOutput;
  }
  stvd::tetmesh::TetMesh mesh;
  try {
    const stvd::tetgen::SurfaceMesh surface = readSurfaceQuietly(input);
    mesh = stvd::tetgen::tetrahedralizeSurface(surface, options, input);
  } catch (const stvd::tetmesh::TetMeshError& e) {
    std::cerr << "stvd tetrahedralize: " << e.what() << std::endl;
    return kExitInput;
  } catch (const std::exception& e) {
    std::cerr << "stvd tetrahedralize: internal error: " << e.what() << std::endl;
    return kExitInternal;
  }
  try {
    writeMesh(base, mesh);
  } catch (const stvd::files::OutputError& e) {
    std::cerr << "stvd tetrahedralize: " << e.what() << std::endl;
    return kExitOutput;
  }
  if (!quiet)
    std::cout << "Tetrahedralized " << input << ": " << mesh.vertexCount() << " vertices, " << mesh.tets.size()
              << " tetrahedra, " << mesh.faces.size() << " boundary faces -> " << base << ".node/.ele/.face\n";
  return kExitOk;
}
