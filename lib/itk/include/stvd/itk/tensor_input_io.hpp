// A tensor volume as stvd's front ends take it in (stvd/imaging/
// tensor_input.hpp), read from its files.
#pragma once

#include <string>

#include "stvd/imaging/tensor_input.hpp"

namespace stvd::imaging {

/// Reads the tensor file and, when options.maskPath is set, the mask file.
/// Throws ImageIoError naming the file: unreadable, wrong layout, or a mask
/// on another grid.
TensorInput readTensorInput(const std::string& path, const TensorInputOptions& options);

}  // namespace stvd::imaging
