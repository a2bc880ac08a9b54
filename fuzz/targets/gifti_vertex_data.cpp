// GIfTI per-vertex files (lib/surface_io): the first byte picks the
// reader (functional/shape values or a label file with its label table)
// and the vertex count the caller asks for (0 to 127).
#include "fuzz_input_file.hpp"
#include "stvd/surface_io/cortical_surface_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t vertices = data[0] & 0x7f;
  const bool labels = (data[0] & 0x80) != 0;
  const stvd::fuzz::FuzzInputFile input(labels ? "regions.label.gii" : "values.shape.gii", data + 1, size - 1);
  try {
    if (labels) stvd::surface_io::readVertexRegions(input.path(), vertices);
    else stvd::surface_io::readVertexValues(input.path(), vertices);
  } catch (const stvd::surface_io::MeshFileError&) {
  }
  return 0;
}
