// PLY surfaces, ASCII and binary of either byte order (lib/surface_io): the
// format line of the header selects the body reader.
#include "fuzz_input_file.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"

STVD_FUZZ_READER("mesh.ply", stvd::surface_io::MeshFileError,
                 [](const std::string& path) { stvd::surface_io::readPly(path); })
