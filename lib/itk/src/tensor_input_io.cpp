#include "stvd/itk/tensor_input_io.hpp"

#include "stvd/itk/image_grid.hpp"
#include "stvd/itk/tensor_volume_io.hpp"

namespace stvd::imaging {

TensorInput readTensorInput(const std::string& path, const TensorInputOptions& options, Interrupter* interrupter) {
  TensorInput input = tensorInputOf(readTensorVolume(path, {options.order, options.frame}, interrupter), path);
  // The mask's header is compared with the tensors' grid before its data
  // are read (image_grid.hpp).
  if (!options.maskPath.empty())
    addMask(input,
            readScalarImageOnGrid(options.maskPath, input.read.volume.geometry, "the mask is", path, interrupter),
            options.maskPath, path);
  return input;
}

}  // namespace stvd::imaging
