#include "stvd/imaging/tensor_input.hpp"

#include <cmath>

#include "stvd/errors.hpp"
#include "stvd/front_end/number_text.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/imaging/tensor_plausibility.hpp"

namespace stvd::imaging {

namespace {

/// Checks `value` as the option's declaration says and sets it.
void setOption(TensorInputOptions& o, const std::string& flag, OptionValue value) {
  const OptionDeclaration& option = tensorInputOption(flag);
  OptionValues values(o.naming);
  values.set(option, std::move(value));
  const TensorInputOptions given = tensorInputOptionsOf(values);
  if (flag == "--tensor-order") o.order = given.order;
  if (flag == "--tensor-frame") o.frame = given.frame;
  if (flag == "--tensor-kind") o.metric.kind = given.metric.kind;
  if (flag == "--diffusion-metric") o.metric.diffusionMetric = given.metric.diffusionMetric;
  if (flag == "--max-anisotropy") o.metric.maxAnisotropy = given.metric.maxAnisotropy;
  if (flag == "--fa-threshold") o.metric.faThreshold = given.metric.faThreshold;
}

}  // namespace

void setTensorOrder(TensorInputOptions& o, const std::string& v) { setOption(o, "--tensor-order", v); }
void setTensorFrame(TensorInputOptions& o, const std::string& v) { setOption(o, "--tensor-frame", v); }
void setTensorKind(TensorInputOptions& o, const std::string& v) { setOption(o, "--tensor-kind", v); }
void setDiffusionMetric(TensorInputOptions& o, const std::string& v) { setOption(o, "--diffusion-metric", v); }
void setMaxAnisotropy(TensorInputOptions& o, double a) { setOption(o, "--max-anisotropy", a); }
void setFaThreshold(TensorInputOptions& o, double t) { setOption(o, "--fa-threshold", t); }

void checkTensorInputOptions(const TensorInputOptions& o) {
  if (o.metric.faThreshold && o.metric.kind != TensorKind::Diffusion)
    throw OptionError(optionName(tensorInputOption("--fa-threshold"), o.naming) + " applies to " +
                      optionWithValue(tensorInputOption("--tensor-kind"), tensorKindName(TensorKind::Diffusion),
                                      o.naming) +
                      " only");
}

TensorInput tensorInputOf(TensorReadResult read, const std::string& name) {
  TensorInput input;
  input.read = std::move(read);
  input.mask = input.read.volume.mask;
  if (!input.mask.empty()) input.maskDescription = "the file's confidence channel";
  for (const std::string& w : input.read.info.warnings) input.warnings.push_back(name + ": " + w);
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
                                     const TensorInputOptions& options, TensorFrameCheck* frameCheck,
                                     Interrupter* interrupter) {
  MetricFromTensors built = buildMetric(input.read.volume.tensors, input.mask, options.metric, interrupter);
  const std::string reason = implausibleTensorsReason(built.counts);
  if (!reason.empty() && !options.acceptImplausible) {
    const auto name = [&](const std::string& flag) { return optionName(tensorInputOption(flag), options.naming); };
    const TensorFileInfo& info = input.read.info;
    throw InputError(inputName + ": " + reason + " as read (" + tensorFileLayoutName(info.layout) + ", order " +
                     tensorOrderName(info.order) + " = " + tensorOrderComponents(info.order) + ", " +
                     tensorFrameName(info.frame) +
                     " frame): most likely a wrong " + name("--tensor-order") + "; check it, " +
                     name("--tensor-frame") + " and " + name("--tensor-kind") + " (stvd info " + inputName +
                     " tries each order), or go on with " +
                     optionSwitchedOn(tensorInputOption("--accept-implausible-tensors"), options.naming));
  }
  // The frame: only diffusion tensors say where tracts run (a metric's
  // principal direction is the costly one, and a metric may be anything).
  TensorFrameCheck check;
  if (options.metric.kind == TensorKind::Diffusion) {
    check = checkTensorFrame(input.read.volume.tensors, input.read.volume.geometry, built.inDomain);
    if (check.verdict == TensorFrameVerdict::Mismatch && !options.acceptMisaligned)
      throw InputError(misalignedTensorsMessage(inputName, check, options));
  } else {
    check.verdict = TensorFrameVerdict::NotChecked;
    check.reason = "metric tensors";
  }
  if (frameCheck) *frameCheck = std::move(check);
  return built;
}

std::string misalignedTensorsMessage(const std::string& inputName, const TensorFrameCheck& check,
                                     const TensorInputOptions& options) {
  return inputName + ": the tensors' frame does not match the image axes: their principal directions follow the "
                     "tracts " + axisTransformWords(check.best) + " " + axisTransformText(check.best) +
         ", not as read (mean streamline " + text::fixed(check.bestMeanMm, 1) + " mm against " +
         text::fixed(check.readMeanMm, 1) + " mm, " + text::withThousands(check.seeds) +
         " seeds): the image was most likely reoriented or flipped (nibabel.as_closest_canonical, say) without "
         "rotating its tensor components; rotate them with it (stvd info " + inputName +
         " shows every frame), or go on with " +
         optionSwitchedOn(tensorInputOption("--accept-misaligned-tensors"), options.naming);
}

}  // namespace stvd::imaging
