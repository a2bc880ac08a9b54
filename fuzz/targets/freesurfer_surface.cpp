// FreeSurfer binary triangle surfaces (lib/surface_io): counts, vertices,
// triangles and the tags after them (useRealRAS, the volume geometry).
#include "fuzz_input_file.hpp"
#include "stvd/surface_io/cortical_surface_files.hpp"

STVD_FUZZ_READER("lh.pial", stvd::surface_io::MeshFileError,
                 [](const std::string& path) { stvd::surface_io::readFreeSurferSurface(path); })
