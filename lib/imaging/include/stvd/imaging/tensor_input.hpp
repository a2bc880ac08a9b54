// A tensor volume as stvd's front ends take it in: the tensors (read from a
// file, stvd/itk/tensor_input_io.hpp, or converted from arrays,
// tensor_arrays.hpp) with the mask that restricts the domain, and how the
// metric is to be made from them.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "stvd/front_end/option_declarations.hpp"
#include "stvd/imaging/scalar_image.hpp"
#include "stvd/imaging/tensor_frame_check.hpp"
#include "stvd/imaging/tensor_layout.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/imaging/tensor_volume.hpp"

namespace stvd::imaging {

/// How to read a tensor file and turn it into a metric (the tool's
/// --tensor-order, --tensor-frame, --tensor-kind, --diffusion-metric,
/// --max-anisotropy, --fa-threshold, --mask and
/// --accept-implausible-tensors, --accept-misaligned-tensors).
struct TensorInputOptions {
  std::optional<TensorOrder> order;
  std::optional<TensorFrame> frame;
  MetricOptions metric;
  std::string maskPath;
  /// Go on when the tensors look read in a wrong layout
  /// (implausibleTensorsReason, tensor_plausibility.hpp).
  bool acceptImplausible = false;
  /// Go on when the tensors' frame does not match the image axes
  /// (checkTensorFrame, tensor_frame_check.hpp).
  bool acceptMisaligned = false;
  /// How messages about these options name them: the tool's flags, or the
  /// Python package's keywords.
  OptionNaming naming = OptionNaming::Flags;
};

// The setters take a value as the user gave it and throw OptionError with
// the tool's message when it is not one of the accepted ones (the checks of
// the options' declarations, stvd/imaging/tensor_input_options.hpp, which the
// front ends use themselves through tensorInputOptionsOf).

/// "lower" (alias "nifti"), "fsl" (alias "upper") or "mrtrix".
void setTensorOrder(TensorInputOptions& options, const std::string& name);
/// "voxel" or "world".
void setTensorFrame(TensorInputOptions& options, const std::string& name);
/// "diffusion" or "metric".
void setTensorKind(TensorInputOptions& options, const std::string& name);
/// "inverse" or "adjugate".
void setDiffusionMetric(TensorInputOptions& options, const std::string& name);
/// At least 1.
void setMaxAnisotropy(TensorInputOptions& options, double cap);
/// In [0, 1).
void setFaThreshold(TensorInputOptions& options, double threshold);
/// OptionError for combinations that make no sense (an FA threshold on
/// metric tensors).
void checkTensorInputOptions(const TensorInputOptions& options);

/// A tensor volume with its mask: the file's own (NRRD confidence) and a
/// mask image's, combined; empty when neither.
struct TensorInput {
  TensorReadResult read;
  std::vector<std::uint8_t> mask;
  /// How the mask came about, for reports: "" or e.g. "mask.nii.gz".
  std::string maskDescription;
  /// What the user should know about the files that were read all the same
  /// (the tensors' and the mask's warnings), each "FILE: text".
  std::vector<std::string> warnings;
};

/// The input of tensors as read (from a file named `name`, or converted
/// from arrays): the file's own mask, if any, and its warnings.
TensorInput tensorInputOf(TensorReadResult read, const std::string& name);

/// Restricts `input` to the voxels where `mask` is neither zero nor NaN,
/// and takes on the mask's warnings. `maskName` and `inputName` name the
/// two in messages and in the mask description. Throws
/// ImageIoError(maskName, ...) when the mask is on another grid than the
/// tensors (geometryMismatch).
void addMask(TensorInput& input, const ScalarImage& mask, const std::string& maskName, const std::string& inputName);

/// buildMetric on the input's tensors and mask, then the checks of the
/// layout: when the tensors are implausible (most of them not positive
/// definite, tensor_plausibility.hpp), InputError naming `inputName`, the
/// layout, order and frame as read and the options to check, unless
/// options.acceptImplausible; for diffusion tensors, when their frame
/// clearly does not match the image axes (a Mismatch of checkTensorFrame,
/// tensor_frame_check.hpp, over the domain), InputError naming the
/// transform that fits, unless options.acceptMisaligned. An inconclusive
/// check never stops a run. `frameCheck`, when given, receives the check
/// (verdict NotChecked for metric tensors). `interrupter`: as for
/// buildMetric.
MetricFromTensors buildCheckedMetric(const std::string& inputName, const TensorInput& input,
                                     const TensorInputOptions& options, TensorFrameCheck* frameCheck = nullptr,
                                     Interrupter* interrupter = nullptr);

/// The message of buildCheckedMetric for a frame that does not match.
std::string misalignedTensorsMessage(const std::string& inputName, const TensorFrameCheck& check,
                                     const TensorInputOptions& options);

}  // namespace stvd::imaging
