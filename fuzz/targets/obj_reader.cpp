// Wavefront OBJ surfaces (lib/surface_io).
#include "fuzz_input_file.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"

STVD_FUZZ_READER("mesh.obj", stvd::surface_io::MeshFileError,
                 [](const std::string& path) { stvd::surface_io::readObj(path); })
