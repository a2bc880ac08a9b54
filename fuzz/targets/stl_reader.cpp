// STL surfaces, ASCII and binary (lib/surface_io): the file's size decides
// which, so one corpus covers both.
#include "fuzz_input_file.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"

STVD_FUZZ_READER("mesh.stl", stvd::surface_io::MeshFileError,
                 [](const std::string& path) { stvd::surface_io::readStl(path); })
