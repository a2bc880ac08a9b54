// A tensor volume as stvd's front ends take it in (stvd/imaging/
// tensor_input.hpp), read from its files.
#pragma once

#include <string>

#include "stvd/imaging/tensor_input.hpp"
#include "stvd/system/interrupter.hpp"

namespace stvd::imaging {

/// Reads the tensor file and, when options.maskPath is set, the mask file.
/// Throws ImageIoError naming the file: unreadable, wrong layout, or a mask
/// on another grid. `interrupter` hears the reads one after the other
/// ("reading tensors", "reading image"; readTensorVolume,
/// readScalarImage); when it asks to stop, Cancelled is thrown.
TensorInput readTensorInput(const std::string& path, const TensorInputOptions& options,
                            Interrupter* interrupter = nullptr);

}  // namespace stvd::imaging
