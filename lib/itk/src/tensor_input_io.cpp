#include "stvd/itk/tensor_input_io.hpp"

#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/itk/tensor_volume_io.hpp"

namespace stvd::imaging {

TensorInput readTensorInput(const std::string& path, const TensorInputOptions& options) {
  TensorInput input = tensorInputOf(readTensorVolume(path, {options.order, options.frame}), path);
  if (!options.maskPath.empty()) addMask(input, readScalarImage(options.maskPath), options.maskPath, path);
  return input;
}

}  // namespace stvd::imaging
