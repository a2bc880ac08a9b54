// GIfTI surfaces (lib/surface_io): the XML, every encoding (ASCII, base64,
// zlib-compressed base64), byte order and array order, the coordinate
// system.
#include "fuzz_input_file.hpp"
#include "stvd/surface_io/cortical_surface_files.hpp"

STVD_FUZZ_READER("mesh.surf.gii", stvd::surface_io::MeshFileError,
                 [](const std::string& path) { stvd::surface_io::readGiftiSurface(path); })
