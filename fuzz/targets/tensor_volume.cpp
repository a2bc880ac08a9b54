// The whole tensor-volume reading path, ITK included: header screening,
// ITK's NIfTI or NRRD reader, layouts, orders and frames. The first byte
// picks the extension (image_file_kinds.hpp) and whether a component order
// is stated.
#include "fuzz_input_file.hpp"
#include "image_file_kinds.hpp"
#include "stvd/errors.hpp"
#include "stvd/itk/tensor_volume_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const stvd::fuzz::FuzzInputFile input(stvd::fuzz::imageFileName(data[0]), data + 1, size - 1);
  stvd::imaging::TensorReadOptions options;
  if (data[0] & 0x10) options.order = stvd::imaging::TensorOrder::Fsl;
  try {
    stvd::imaging::readTensorVolume(input.path(), options);
  } catch (const stvd::imaging::ImageIoError&) {
  }
  return 0;
}
