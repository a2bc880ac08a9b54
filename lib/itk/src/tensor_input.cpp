#include "stvd/itk/image_grid.hpp"
#include "stvd/itk/tensor_input.hpp"

#include <cmath>

#include "stvd/front_end_errors.hpp"
#include "stvd/itk/tensor_plausibility.hpp"

namespace stvd::imaging {

void setTensorOrder(TensorInputOptions& o, const std::string& v) {
  o.order = parseTensorOrder(v);
  if (!o.order) throw OptionError("--tensor-order: '" + v + "' is not one of lower, fsl, mrtrix");
}

void setTensorFrame(TensorInputOptions& o, const std::string& v) {
  o.frame = parseTensorFrame(v);
  if (!o.frame) throw OptionError("--tensor-frame: '" + v + "' is not one of voxel, world");
}

void setTensorKind(TensorInputOptions& o, const std::string& v) {
  const auto kind = parseTensorKind(v);
  if (!kind) throw OptionError("--tensor-kind: '" + v + "' is not one of diffusion, metric");
  o.metric.kind = *kind;
}

void setDiffusionMetric(TensorInputOptions& o, const std::string& v) {
  const auto metric = parseDiffusionMetric(v);
  if (!metric) throw OptionError("--diffusion-metric: '" + v + "' is not one of inverse, adjugate");
  o.metric.diffusionMetric = *metric;
}

void setMaxAnisotropy(TensorInputOptions& o, double a) {
  if (!(a >= 1.0)) throw OptionError("--max-anisotropy must be at least 1");
  o.metric.maxAnisotropy = a;
}

void setFaThreshold(TensorInputOptions& o, double t) {
  if (!(t >= 0.0 && t < 1.0)) throw OptionError("--fa-threshold must be in [0, 1)");
  o.metric.faThreshold = t;
}

void checkTensorInputOptions(const TensorInputOptions& o) {
  if (o.metric.faThreshold && o.metric.kind != TensorKind::Diffusion)
    throw OptionError("--fa-threshold applies to --tensor-kind diffusion only");
}

TensorInput tensorInputOf(TensorReadResult read, const std::string& name) {
  TensorInput input;
  input.read = std::move(read);
  input.mask = input.read.volume.mask;
  if (!input.mask.empty()) input.maskDescription = "the file's confidence channel";
  for (const std::string& w : input.read.info.warnings) input.warnings.push_back(name + ": " + w);
  return input;
}

TensorInput readTensorInput(const std::string& path, const TensorInputOptions& options) {
  TensorInput input = tensorInputOf(readTensorVolume(path, {options.order, options.frame}), path);
  // The mask's header is compared with the tensors' grid before its data
  // are read (image_grid.hpp).
  if (!options.maskPath.empty())
    addMask(input, readScalarImageOnGrid(options.maskPath, input.read.volume.geometry, "the mask is", path),
            options.maskPath, path);
  return input;
}

void addMask(TensorInput& input, const ScalarImage& mask, const std::string& maskName, const std::string& inputName) {
  for (const std::string& w : mask.warnings) input.warnings.push_back(maskName + ": " + w);
  requireSameGrid(mask.geometry, input.read.volume.geometry, maskName, "the mask is", inputName);
  if (input.mask.empty()) input.mask.assign(mask.values.size(), 1);
  for (std::size_t v = 0; v < mask.values.size(); ++v)
    if (mask.values[v] == 0.f || std::isnan(mask.values[v])) input.mask[v] = 0;
  input.maskDescription =
      input.maskDescription.empty() ? maskName : maskName + " and " + input.maskDescription;
}

MetricFromTensors buildCheckedMetric(const std::string& inputName, const TensorInput& input,
                                     const TensorInputOptions& options) {
  MetricFromTensors built = buildMetric(input.read.volume.tensors, input.mask, options.metric);
  const std::string reason = implausibleTensorsReason(built.counts);
  if (!reason.empty() && !options.acceptImplausible) {
    const TensorFileInfo& info = input.read.info;
    throw InputError(inputName + ": " + reason + " as read (" + tensorFileLayoutName(info.layout) + ", order " +
                     tensorOrderName(info.order) + " = " + tensorOrderComponents(info.order) + ", " +
                     tensorFrameName(info.frame) +
                     " frame): most likely a wrong --tensor-order; check it, --tensor-frame and --tensor-kind (stvd "
                     "info " + inputName + " tries each order), or go on with --accept-implausible-tensors");
  }
  return built;
}

}  // namespace stvd::imaging
