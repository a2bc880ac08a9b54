// `stvd distance` over polygon surfaces (tools/surface_distance_command.cpp).
#pragma once

namespace stvd::tool {

/// True when `stvd distance` is called for a surface: its input (argv[2])
/// is a .obj/.off/.ply mesh, or --seed-vertex is given.
bool isSurfaceDistanceCall(int argc, char** argv);
int runSurfaceDistance(int argc, char** argv);

}  // namespace stvd::tool
