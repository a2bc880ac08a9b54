#include "stvd/itk/tensor_input.hpp"

#include <cmath>


namespace stvd::imaging {

TensorInput readTensorInput(const std::string& path, const TensorInputOptions& options) {
  TensorInput input;
  input.read = readTensorVolume(path, {options.order, options.frame});
  input.mask = input.read.volume.mask;
  if (!input.mask.empty()) input.maskDescription = "the file's confidence channel";
  if (!options.maskPath.empty()) addMask(input, readScalarImage(options.maskPath), options.maskPath, path);
  return input;
}

void addMask(TensorInput& input, const ScalarImage& mask, const std::string& maskName, const std::string& inputName) {
  requireSameGrid(mask.geometry, input.read.volume.geometry, maskName, "the mask is", inputName);
  if (input.mask.empty()) input.mask.assign(mask.values.size(), 1);
  for (std::size_t v = 0; v < mask.values.size(); ++v)
    if (mask.values[v] == 0.f || std::isnan(mask.values[v])) input.mask[v] = 0;
  input.maskDescription =
      input.maskDescription.empty() ? maskName : maskName + " and " + input.maskDescription;
}

}  // namespace stvd::imaging
