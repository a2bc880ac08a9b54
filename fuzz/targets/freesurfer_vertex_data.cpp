// FreeSurfer per-vertex files (lib/surface_io): the first byte picks the
// reader (bits 0-1: curv, .mgh/.mgz, .annot, .label) and the vertex count
// the caller asks for (bits 2-7: 0 to 63).
#include "fuzz_input_file.hpp"
#include "stvd/surface_io/cortical_surface_files.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t vertices = data[0] >> 2;
  static const char* const names[4] = {"lh.curv", "values.mgz", "lh.aparc.annot", "lh.region.label"};
  const int kind = data[0] & 3;
  const stvd::fuzz::FuzzInputFile input(names[kind], data + 1, size - 1);
  try {
    if (kind < 2) stvd::surface_io::readVertexValues(input.path(), vertices);
    else stvd::surface_io::readVertexRegions(input.path(), vertices);
  } catch (const stvd::surface_io::MeshFileError&) {
  }
  return 0;
}
