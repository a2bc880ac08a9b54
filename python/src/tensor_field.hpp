// A tensor volume made ready for propagations: its tensors (from a file or
// an array), its mask, the metric and the domain, built as `stvd distance`
// builds them. Propagations, paths and connectivity from Python share one.
#pragma once

#include <pybind11/pybind11.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "stvd/imaging/scalar_image.hpp"
#include "stvd/imaging/tensor_input.hpp"
#include "stvd/metric/metric_field.hpp"

namespace stvd::python {

namespace py = pybind11;

struct TensorField {
  /// How the input is named in messages: the path, or "tensors".
  std::string name;
  /// What came in, for reports (tensor_info): "file", "NiBabel image" or
  /// "array"; what it was ("the path", "NiBabel image of FILE", "array of
  /// shape (112, 112, 32, 3, 3), float64"); and its layout as given (a
  /// file's or image's as the tool names it, an array's by its shape).
  std::string inputKind = "file";
  std::string inputDescription;
  std::string layoutDescription;
  /// An (X, Y, Z, 3, 3) array: no component order.
  bool matrices = false;
  imaging::TensorInputOptions options;
  imaging::TensorInput input;
  imaging::MetricVoxelCounts counts;
  /// Whether the tensors' frame matches the image axes (tensor_frame_check.hpp).
  imaging::TensorFrameCheck frameCheck;
  std::vector<std::uint8_t> inDomain;
  RiemannianMetric metric;

  const GridGeometry& geometry() const { return input.read.volume.geometry; }
  /// FA of the tensors in the domain (0 elsewhere), computed once.
  const std::vector<float>& fractionalAnisotropy() const;

 private:
  mutable std::once_flag faOnce_;
  mutable std::vector<float> fa_;
};

/// The tensor options from the keywords (None: the library's default),
/// through the library's setters and checks.
imaging::TensorInputOptions tensorOptions(const std::optional<std::string>& order,
                                          const std::optional<std::string>& frame,
                                          const std::optional<std::string>& kind,
                                          const std::optional<std::string>& diffusionMetric,
                                          const std::optional<double>& maxAnisotropy,
                                          const std::optional<double>& faThreshold, bool acceptImplausible = false,
                                          bool acceptMisaligned = false);

/// A scalar image given from Python: a path (read through ITK), or a tuple
/// (array, affine or None, zooms or None, name); the array may be a lazy
/// one with a shape (NiBabel's ArrayProxy). Without an affine the array is
/// taken to be on `grid` when its shape is the grid's size (and is reported
/// on another grid otherwise). An image on another grid than `grid` is
/// refused before its data are read (ImageIoError "<name>: <subject> on
/// another grid than <referenceName> (...)"): from a file's header, from a
/// lazy array's shape.
imaging::ScalarImage scalarImageOf(const py::handle& spec, const GridGeometry& grid, const std::string& subject,
                                   const std::string& referenceName);
/// The same for a label image: a path read by imaging::readLabelImage, or
/// an array whose values follow the same rules (integers exactly).
imaging::LabelImage labelImageOf(const py::handle& spec, const GridGeometry& grid, const std::string& subject,
                                 const std::string& referenceName);
/// How such an image is named in messages: its path, or the name in the tuple.
std::string scalarImageName(const py::handle& spec);

/// Reads a tensor file (and a mask) and builds the field. GIL released.
std::shared_ptr<TensorField> fieldFromFile(const std::string& path, imaging::TensorInputOptions options,
                                           const py::handle& mask);

/// Converts a tensor array with its affine and builds the field. `niftiIntent`
/// says where the array came from: None for a plain array (six components
/// in a stated order, or 3x3 matrices), true or false for a NiBabel image
/// with or without the SYMMATRIX intent (read as the tool reads that file).
std::shared_ptr<TensorField> fieldFromArray(const py::handle& tensors, const py::handle& affine,
                                            const std::optional<std::array<double, 3>>& zooms,
                                            const std::optional<bool>& niftiIntent, const std::string& name,
                                            imaging::TensorInputOptions options, const py::handle& mask);

/// The field as a picklable state (a tuple of plain values and bytes: the
/// tensors as read, the masks, the options, the file information) and back.
/// The metric and the domain are not stored: `fieldFromState` builds them
/// again from the tensors and options, as the field was built, the same
/// values bit for bit.
py::tuple fieldState(const TensorField& field);
std::shared_ptr<TensorField> fieldFromState(const py::tuple& state);

}  // namespace stvd::python
