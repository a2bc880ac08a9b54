// The whole MRtrix image reading path (our own parser, lib/itk/src/
// mrtrix_image.cpp, and the adapter's conversions): the input is the
// content of a .mif file, read as a scalar image, as a label image and as a
// tensor volume, the three roles an MRtrix image has in stvd. A reader that
// returns must return one value (or tensor) per voxel of its grid.
#include "fuzz_input_file.hpp"
#include "stvd/errors.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/itk/tensor_volume_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const stvd::fuzz::FuzzInputFile input("image.mif", data, size);
  try {
    const stvd::imaging::ScalarImage image = stvd::imaging::readScalarImage(input.path());
    if (image.values.size() != image.geometry.voxelCount()) __builtin_trap();
  } catch (const stvd::imaging::ImageIoError&) {
  }
  try {
    const stvd::imaging::LabelImage image = stvd::imaging::readLabelImage(input.path());
    if (image.labels.size() != image.geometry.voxelCount()) __builtin_trap();
  } catch (const stvd::imaging::ImageIoError&) {
  }
  try {
    const stvd::imaging::TensorReadResult read = stvd::imaging::readTensorVolume(input.path());
    if (read.volume.tensors.size() != read.volume.geometry.voxelCount()) __builtin_trap();
  } catch (const stvd::imaging::ImageIoError&) {
  }
  return 0;
}
