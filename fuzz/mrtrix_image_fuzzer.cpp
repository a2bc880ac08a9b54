// libFuzzer target of our MRtrix image parser (lib/itk/src/mrtrix_image.cpp):
// the input is the content of a .mif file. Every input must either parse
// or fail with ImageIoError; crashes, sanitizer reports and other
// exceptions are findings.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "stvd/itk/image_io_error.hpp"
#include "stvd/itk/mrtrix_image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const stvd::imaging::MrtrixImage image = stvd::imaging::parseMrtrixImage(bytes, "fuzz.mif");
    if (image.values.size() != image.header.elementCount()) __builtin_trap();
  } catch (const stvd::imaging::ImageIoError&) {
  }
  return 0;
}
