// `stvd distance` over polygon surfaces (tools/surface_distance_command.cpp).
#pragma once

#include <string>

namespace stvd::tool {

/// True when `stvd distance` is called for a surface: an argument other
/// than the output's is a .obj/.off/.ply file, or --seed-vertex is given.
bool isSurfaceDistanceCall(int argc, char** argv);
int runSurfaceDistance(int argc, char** argv);
/// The help of `stvd distance MESH --help`.
std::string surfaceDistanceHelp();
/// Its option sections alone, for `stvd distance --help`.
std::string surfaceOptionsHelp();

}  // namespace stvd::tool
