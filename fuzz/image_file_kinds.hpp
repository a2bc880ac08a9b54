// The whole-path image targets take a file-name extension from the first
// byte of the fuzzer's input, so that one corpus covers every reader.
#pragma once

#include <cstddef>
#include <cstdint>

namespace stvd::fuzz {

inline const char* imageFileName(std::uint8_t selector) {
  static const char* const names[] = {"image.nii", "image.nii.gz", "image.nrrd", "image.nhdr"};
  return names[selector % 4];
}

}  // namespace stvd::fuzz
