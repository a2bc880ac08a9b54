// The whole scalar-image reading path, ITK included (masks, seed and label
// images, references): readImageGrid (a side input's grid from its header
// alone, screened without its data), readScalarImage and readLabelImage. The
// first byte picks the extension (image_file_kinds.hpp).
#include "fuzz_input_file.hpp"
#include "image_file_kinds.hpp"
#include "stvd/errors.hpp"
#include "stvd/itk/image_grid.hpp"
#include "stvd/itk/scalar_image_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const stvd::fuzz::FuzzInputFile input(stvd::fuzz::imageFileName(data[0]), data + 1, size - 1);
  try {
    stvd::imaging::readImageGrid(input.path());
  } catch (const stvd::imaging::ImageIoError&) {
  }
  try {
    stvd::imaging::readScalarImage(input.path());
  } catch (const stvd::imaging::ImageIoError&) {
  }
  try {
    stvd::imaging::readLabelImage(input.path());
  } catch (const stvd::imaging::ImageIoError&) {
  }
  return 0;
}
