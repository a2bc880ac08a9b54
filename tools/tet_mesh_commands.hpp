// The tetrahedral-mesh side of `stvd`: distances over a TetGen mesh
// (reached from `stvd distance` when the input is a .node or .ele file) and
// `stvd tetrahedralize`, which runs the separate TetGen program.
#pragma once

#include <string>

namespace stvd::tool {

/// Whether `stvd distance` should treat `input` as a tetrahedral mesh.
bool isTetMeshInput(const std::string& input);
/// The option sections of `stvd distance MESH.node --help`, for `stvd distance --help`.
std::string tetMeshOptionsHelp();
/// `stvd distance MESH.node ...`.
int runTetMeshDistance(int argc, char** argv);
/// `stvd tetrahedralize SURFACE -o MESH ...`.
int runTetrahedralize(int argc, char** argv);

}  // namespace stvd::tool
