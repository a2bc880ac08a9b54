// The whole FOD reading path (stvd/itk/fod_volume_io.hpp): MRtrix images
// through our own parser, NIfTI through the header screening and ITK, then
// the count of volumes, the coefficients' checks and their layout. The
// first byte picks the file's extension and the options: bits 0-1 .mif,
// .nii, .nii.gz or .mif.gz; bit 4 states a basis; bit 5 the voxel frame. A
// reader that returns must return one coefficient set per voxel, of a
// degree it names, and finite amplitudes.
#include <cmath>

#include "fuzz_input_file.hpp"
#include "stvd/errors.hpp"
#include "stvd/itk/fod_volume_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  static const char* const names[] = {"image.mif", "image.nii", "image.nii.gz", "image.mif.gz"};
  const stvd::fuzz::FuzzInputFile input(names[data[0] % 4], data + 1, size - 1);
  stvd::imaging::FodReadOptions options;
  if (data[0] & 0x10) options.basis = "descoteaux07_legacy";
  if (data[0] & 0x20) options.frame = stvd::imaging::FodFrame::Voxel;
  try {
    const stvd::imaging::FodField fod = stvd::imaging::readFodVolume(input.path(), options);
    if (fod.lmax < 0 || fod.lmax > stvd::imaging::kMaxShDegree || fod.lmax % 2 != 0) __builtin_trap();
    if (fod.coefficients.size() != fod.geometry.voxelCount() * static_cast<std::size_t>(fod.coefficientCount()))
      __builtin_trap();
    if (fod.geometry.voxelCount() > 0 && !std::isfinite(fod.amplitude(0, stvd::Vec3d{0.3, -0.4, 0.87})))
      __builtin_trap();
  } catch (const stvd::imaging::ImageIoError&) {
  }
  return 0;
}
