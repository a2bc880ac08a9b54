// `stvd distance` over polygon surfaces (tools/surface_distance_command.cpp).
#pragma once

namespace stvd::tool {

/// True when `stvd distance` is called for a surface: an argument other
/// than the output's is a .obj/.off/.ply file, or --seed-vertex is given.
bool isSurfaceDistanceCall(int argc, char** argv);
int runSurfaceDistance(int argc, char** argv);

}  // namespace stvd::tool
