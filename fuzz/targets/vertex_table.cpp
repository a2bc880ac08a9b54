// Per-vertex and per-face tables (the field:, tensors: and face-tensors:
// metric files of surface distances). The first byte picks the shape the
// caller asks for: 3 or 6 columns, and 0 to 63 rows.
#include "fuzz_input_file.hpp"
#include "stvd/surface_io/surface_mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::size_t columns = (data[0] & 0x80) ? 6 : 3, rows = data[0] & 0x3f;
  const stvd::fuzz::FuzzInputFile input("table.txt", data + 1, size - 1);
  try {
    stvd::surface_io::readVertexTable(input.path(), columns, rows, (data[0] & 0x40) ? "face" : "vertex");
  } catch (const stvd::surface_io::MeshFileError&) {
  }
  return 0;
}
