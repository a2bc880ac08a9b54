#include "tensor_field.hpp"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "array_access.hpp"
#include "stvd/imaging/tensor_arrays.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/itk/image_grid.hpp"
#include "stvd/itk/tensor_volume_io.hpp"

namespace stvd::python {

const std::vector<float>& TensorField::fractionalAnisotropy() const {
  std::call_once(faOnce_, [this] { fa_ = imaging::fractionalAnisotropyMap(input.read.volume.tensors, inDomain); });
  return fa_;
}

imaging::TensorInputOptions tensorOptions(const std::optional<std::string>& order,
                                          const std::optional<std::string>& frame,
                                          const std::optional<std::string>& kind,
                                          const std::optional<std::string>& diffusionMetric,
                                          const std::optional<double>& maxAnisotropy,
                                          const std::optional<double>& faThreshold, bool acceptImplausible,
                                          bool acceptMisaligned) {
  // Checked by the options' declarations, with messages in keyword names.
  OptionValues values(OptionNaming::Keywords);
  const auto option = [](const char* flag) -> const OptionDeclaration& { return imaging::tensorInputOption(flag); };
  if (order) values.set(option("--tensor-order"), *order);
  if (frame) values.set(option("--tensor-frame"), *frame);
  if (kind) values.set(option("--tensor-kind"), *kind);
  if (diffusionMetric) values.set(option("--diffusion-metric"), *diffusionMetric);
  if (maxAnisotropy) values.set(option("--max-anisotropy"), *maxAnisotropy);
  if (faThreshold) values.set(option("--fa-threshold"), *faThreshold);
  if (acceptImplausible) values.set(option("--accept-implausible-tensors"), true);
  if (acceptMisaligned) values.set(option("--accept-misaligned-tensors"), true);
  return imaging::tensorInputOptionsOf(values);
}

std::string scalarImageName(const py::handle& spec) {
  return py::isinstance<py::str>(spec) ? spec.cast<std::string>() : spec.cast<py::tuple>()[3].cast<std::string>();
}

namespace {

/// The shape of the array of a tuple (array, affine, zooms, name), without
/// reading a lazy array's data (NiBabel's ArrayProxy has a shape).
std::vector<py::ssize_t> shapeOf(const py::handle& data, const std::string& name) {
  if (!py::isinstance<py::array>(data) && py::hasattr(data, "shape") && py::hasattr(data, "dtype")) {
    std::vector<py::ssize_t> shape;
    for (const py::handle extent : py::iterable(data.attr("shape"))) shape.push_back(extent.cast<py::ssize_t>());
    return shape;
  }
  const py::array values = numericArray(data, name);
  return std::vector<py::ssize_t>(values.shape(), values.shape() + values.ndim());
}

/// The grid of an image given as a tuple (array, affine or None, zooms or
/// None, name): the affine's, or `grid` with the array's size when there is
/// none (reported as another grid when the sizes differ).
GridGeometry arrayGeometry(const py::tuple& given, const std::vector<py::ssize_t>& shape, const GridGeometry& grid,
                           const std::string& name) {
  if (shape.size() != 3) {
    std::string text = "(";
    for (std::size_t d = 0; d < shape.size(); ++d) text += (d ? ", " : "") + std::to_string(shape[d]);
    throw py::value_error(name + ": expected an array of shape (X, Y, Z), got shape " + text +
                          (shape.size() == 1 ? ",)" : ")"));
  }
  const std::array<std::size_t, 3> size{static_cast<std::size_t>(shape[0]), static_cast<std::size_t>(shape[1]),
                                        static_cast<std::size_t>(shape[2])};
  if (given[1].is_none()) {
    GridGeometry g = grid;
    g.size = size;
    return g;
  }
  std::optional<std::array<double, 3>> zooms;
  if (!given[2].is_none()) zooms = given[2].cast<std::array<double, 3>>();
  try {
    return imaging::gridGeometryFromRasAffine(affineOf(given[1], name + " affine"), size, zooms);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(name + ": " + e.what());
  }
}

}  // namespace

imaging::ScalarImage scalarImageOf(const py::handle& spec, const GridGeometry& grid, const std::string& subject,
                                   const std::string& referenceName) {
  const std::string name = scalarImageName(spec);
  if (py::isinstance<py::str>(spec)) {
    py::gil_scoped_release release;
    return imaging::readScalarImageOnGrid(name, grid, subject, referenceName);
  }
  const py::tuple given = spec.cast<py::tuple>();
  imaging::ScalarImage image;
  // A masked array's masked voxels are 0: outside a mask, in no seed region.
  const py::object data = splitMaskedArray(given[0]).values;
  image.geometry = arrayGeometry(given, shapeOf(data, name), grid, name);
  imaging::requireSameGrid(image.geometry, grid, name, subject, referenceName);  // before a lazy array is read
  image.values = voxelValues(numericArray(data, name));
  return image;
}

imaging::LabelImage labelImageOf(const py::handle& spec, const GridGeometry& grid, const std::string& subject,
                                 const std::string& referenceName) {
  const std::string name = scalarImageName(spec);
  if (py::isinstance<py::str>(spec)) {
    py::gil_scoped_release release;
    return imaging::readLabelImageOnGrid(name, grid, subject, referenceName);
  }
  const py::tuple given = spec.cast<py::tuple>();
  imaging::LabelImage image;
  // A masked array's masked voxels are 0: in no region.
  const py::object data = splitMaskedArray(given[0]).values;
  image.geometry = arrayGeometry(given, shapeOf(data, name), grid, name);
  imaging::requireSameGrid(image.geometry, grid, name, subject, referenceName);  // before a lazy array is read
  image.labels = voxelLabels(numericArray(data, name), name, image.geometry);
  return image;
}

namespace {

/// The 3x3 matrices must be symmetric (to single precision: a matrix made
/// as V diag(l) V^T in floating point is symmetric only up to rounding);
/// their upper triangles are used.
template <class T>
void requireSymmetric(const T* data, const std::array<std::size_t, 3>& size,
                      const std::array<std::ptrdiff_t, 3>& voxelStride, std::ptrdiff_t row, std::ptrdiff_t column,
                      const std::string& name) {
  for (std::size_t k = 0; k < size[2]; ++k)
    for (std::size_t j = 0; j < size[1]; ++j)
      for (std::size_t i = 0; i < size[0]; ++i) {
        const T* m = data + static_cast<std::ptrdiff_t>(i) * voxelStride[0] +
                     static_cast<std::ptrdiff_t>(j) * voxelStride[1] + static_cast<std::ptrdiff_t>(k) * voxelStride[2];
        double largest = 0.0;
        for (int r = 0; r < 3; ++r)
          for (int c = 0; c < 3; ++c) largest = std::max(largest, std::abs(double(m[r * row + c * column])));
        for (int r = 0; r < 3; ++r)
          for (int c = r + 1; c < 3; ++c) {
            const double upper = m[r * row + c * column], lower = m[c * row + r * column];
            if (std::abs(upper - lower) > 1e-5 * largest)
              throw std::invalid_argument(name + ": the matrix of voxel (" + std::to_string(i) + ", " +
                                          std::to_string(j) + ", " + std::to_string(k) + ") is not symmetric");
          }
      }
}

/// Builds the metric and the domain as `stvd distance` does, without the GIL.
std::shared_ptr<TensorField> finishField(std::shared_ptr<TensorField> field, const py::handle& mask) {
  if (!mask.is_none())
    imaging::addMask(field->input, scalarImageOf(mask, field->geometry(), "the mask is", field->name),
                     scalarImageName(mask), field->name);
  py::gil_scoped_release release;
  imaging::MetricFromTensors built =
      imaging::buildCheckedMetric(field->name, field->input, field->options, &field->frameCheck);
  imaging::requireNonEmptyDomain(field->name, built.counts, !field->input.mask.empty(), field->options.metric);
  field->counts = built.counts;
  field->inDomain = std::move(built.inDomain);
  field->metric = RiemannianMetric(std::move(built.metric), &field->inDomain);
  return field;
}

}  // namespace

std::shared_ptr<TensorField> fieldFromFile(const std::string& path, imaging::TensorInputOptions options,
                                           const py::handle& mask) {
  auto field = std::make_shared<TensorField>();
  field->name = path;
  field->options = options;
  {
    py::gil_scoped_release release;
    field->input = imaging::tensorInputOf(imaging::readTensorVolume(path, {options.order, options.frame}), path);
  }
  field->inputKind = "file";
  field->inputDescription = path;
  field->layoutDescription = imaging::tensorFileLayoutName(field->input.read.info.layout);
  return finishField(std::move(field), mask);
}

std::shared_ptr<TensorField> fieldFromArray(const py::handle& tensors, const py::handle& affine,
                                            const std::optional<std::array<double, 3>>& zooms,
                                            const std::optional<bool>& niftiIntent, const std::string& name,
                                            imaging::TensorInputOptions options, const py::handle& mask) {
  // A masked array: its values where they are not masked, and the voxels
  // with a masked component outside the domain (as a mask= would leave them).
  const MaskedSplit split = splitMaskedArray(tensors);
  const py::array array = numericArray(split.values, name);
  requireFloatingPoint(array, name);
  const py::ssize_t ndim = array.ndim();
  const bool matrices = ndim == 5 && array.shape(3) == 3 && array.shape(4) == 3;
  const bool sixLast = (ndim == 4 && array.shape(3) == 6) || (ndim == 5 && array.shape(3) == 1 && array.shape(4) == 6);
  if (!matrices && !sixLast)
    throw py::value_error(name + ": expected an array of shape (X, Y, Z, 6) or (X, Y, Z, 3, 3)" +
                          std::string(niftiIntent ? " (or X, Y, Z, 1, 6 from a NIfTI file)" : "") + ", got shape " +
                          shapeText(array));
  if (affine.is_none())
    throw py::value_error(name + ": an array needs affine=, the 4x4 matrix from voxel indices to RAS millimetres");

  auto field = std::make_shared<TensorField>();
  field->name = name;
  field->options = options;
  // An image's name is its file's (set by the package), or the default.
  if (niftiIntent) {
    field->inputKind = "NiBabel image";
    field->inputDescription = name == "tensors" ? "NiBabel image (not from a file)" : "NiBabel image of " + name;
  } else {
    field->inputKind = "array";
    field->inputDescription = "array of shape " + shapeText(array) + ", " + std::string(py::str(array.dtype()));
  }
  imaging::TensorFileInfo& info = field->input.read.info;
  info.componentType = array.itemsize() == 4 ? "float" : "double";
  imaging::TensorComponentLayout layout;
  const py::ssize_t item = array.itemsize();
  const py::ssize_t last = array.strides(ndim - 1) / item;
  if (matrices) {
    if (options.order)
      throw py::value_error(name + ": tensor_order applies to six components per voxel, not to 3x3 matrices");
    info.layout = imaging::TensorFileLayout::NiftiSixVolumes;
    info.order = imaging::TensorOrder::Fsl;  // the upper triangle, row by row
    const py::ssize_t row = array.strides(3) / item;
    layout.componentOffset = {0, last, 2 * last, row + last, row + 2 * last, 2 * row + 2 * last};
    field->layoutDescription = "(X, Y, Z, 3, 3) array of symmetric matrices";
    field->matrices = true;
  } else {
    if (!niftiIntent && !options.order)
      throw py::value_error(name + ": an array of six values per voxel does not say its component order; state it "
                                   "with tensor_order='fsl', 'mrtrix' or 'lower'");
    info.layout = niftiIntent.value_or(false) && ndim == 5 ? imaging::TensorFileLayout::NiftiSymMatrix5D
                                                           : imaging::TensorFileLayout::NiftiSixVolumes;
    info.order = imaging::resolveTensorOrder(name, info.layout, options.order);
    for (int q = 0; q < 6; ++q) layout.componentOffset[q] = q * last;
    field->layoutDescription = niftiIntent ? imaging::tensorFileLayoutName(info.layout)
                                           : std::string(ndim == 5 ? "(X, Y, Z, 1, 6)" : "(X, Y, Z, 6)") + " array";
  }
  layout.order = info.order;
  info.frameWasStated = options.frame.has_value();
  info.frame = options.frame.value_or(imaging::defaultTensorFrame(info.layout, info.order));
  for (int a = 0; a < 3; ++a) layout.voxelStride[a] = array.strides(a) / item;
  const std::array<std::size_t, 3> size{static_cast<std::size_t>(array.shape(0)),
                                        static_cast<std::size_t>(array.shape(1)),
                                        static_cast<std::size_t>(array.shape(2))};
  const std::array<double, 16> matrix = affineOf(affine, "affine");
  GridGeometry& g = field->input.read.volume.geometry;
  try {
    g = imaging::gridGeometryFromRasAffine(matrix, size, zooms);
  } catch (const std::invalid_argument& e) {
    throw py::value_error(name + ": " + std::string(e.what()));
  }
  const imaging::Matrix3 toLps = imaging::componentFrameToLps(info, g);
  // The views are taken with the GIL; reading through them needs none.
  withFloatView(array, [&](const auto& view) {
    const py::ssize_t row = matrices ? array.strides(3) / item : 0;
    py::gil_scoped_release release;
    if (matrices) requireSymmetric(view.data, size, layout.voxelStride, row, last, name);
    field->input.read.volume.tensors = imaging::tensorsFromArray(view.data, size, layout, toLps);
  });
  if (!split.masked.is_none()) {
    py::tuple components(ndim - 3);
    for (py::ssize_t d = 3; d < ndim; ++d) components[d - 3] = py::int_(d);
    const std::vector<float> maskedVoxels = voxelValues(numericArray(split.masked.attr("any")(components), name));
    imaging::TensorInput& input = field->input;
    input.mask.assign(maskedVoxels.size(), 1);
    for (std::size_t v = 0; v < maskedVoxels.size(); ++v)
      if (maskedVoxels[v] != 0.f) input.mask[v] = 0;
    input.maskDescription = "the mask of " + name + " (numpy.ma)";
  }
  return finishField(std::move(field), mask);
}

namespace {

constexpr const char* kFieldStateTag = "stvd.TensorField/1";

template <class T>
py::bytes bytesOf(const std::vector<T>& values) {
  return py::bytes(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

template <class T>
std::vector<T> vectorOf(const py::handle& bytes, const char* what) {
  const std::string data = bytes.cast<std::string>();
  if (data.size() % sizeof(T) != 0) throw py::value_error(std::string("unpickling stvd: ") + what + " is truncated");
  std::vector<T> values(data.size() / sizeof(T));
  if (!data.empty()) std::memcpy(values.data(), data.data(), data.size());
  return values;
}

template <class E>
py::object optionalEnum(const std::optional<E>& value) {
  return value ? py::object(py::int_(static_cast<int>(*value))) : py::object(py::none());
}

template <class E>
std::optional<E> enumOrNone(const py::handle& value) {
  if (value.is_none()) return std::nullopt;
  return static_cast<E>(value.cast<int>());
}

}  // namespace

py::tuple fieldState(const TensorField& f) {
  const imaging::TensorInputOptions& o = f.options;
  const py::tuple options = py::make_tuple(
      optionalEnum(o.order), optionalEnum(o.frame), static_cast<int>(o.metric.kind),
      static_cast<int>(o.metric.diffusionMetric), o.metric.maxAnisotropy, o.metric.faThreshold, o.maskPath,
      o.acceptImplausible, static_cast<int>(o.naming), o.acceptMisaligned);
  const GridGeometry& g = f.geometry();
  const py::tuple geometry = py::make_tuple(g.size, g.spacing, g.origin, g.direction);
  const imaging::TensorFileInfo& i = f.input.read.info;
  const py::tuple info = py::make_tuple(static_cast<int>(i.layout), static_cast<int>(i.order), static_cast<int>(i.frame),
                                        i.frameWasStated, i.hasMeasurementFrame, i.measurementFrameLps, i.nrrdSpace,
                                        i.componentsToLps, i.componentType, i.warnings);
  return py::make_tuple(kFieldStateTag, f.name, options, geometry, bytesOf(f.input.read.volume.tensors),
                        bytesOf(f.input.read.volume.mask), info, bytesOf(f.input.mask), f.input.maskDescription,
                        f.input.warnings,
                        py::make_tuple(f.inputKind, f.inputDescription, f.layoutDescription, f.matrices));
}

std::shared_ptr<TensorField> fieldFromState(const py::tuple& state) {
  if (state.size() != 11 || !py::isinstance<py::str>(state[0]) || state[0].cast<std::string>() != kFieldStateTag)
    throw py::value_error("unpickling stvd: not the state of an stvd.TensorField of this version");
  auto f = std::make_shared<TensorField>();
  f->name = state[1].cast<std::string>();
  const py::tuple o = state[2].cast<py::tuple>();
  f->options.order = enumOrNone<imaging::TensorOrder>(o[0]);
  f->options.frame = enumOrNone<imaging::TensorFrame>(o[1]);
  f->options.metric.kind = static_cast<imaging::TensorKind>(o[2].cast<int>());
  f->options.metric.diffusionMetric = static_cast<imaging::DiffusionMetric>(o[3].cast<int>());
  f->options.metric.maxAnisotropy = o[4].cast<std::optional<double>>();
  f->options.metric.faThreshold = o[5].cast<std::optional<double>>();
  f->options.maskPath = o[6].cast<std::string>();
  f->options.acceptImplausible = o[7].cast<bool>();
  f->options.naming = static_cast<OptionNaming>(o[8].cast<int>());
  f->options.acceptMisaligned = o[9].cast<bool>();
  const py::tuple g = state[3].cast<py::tuple>();
  GridGeometry& geometry = f->input.read.volume.geometry;
  geometry.size = g[0].cast<std::array<std::size_t, 3>>();
  geometry.spacing = g[1].cast<std::array<double, 3>>();
  geometry.origin = g[2].cast<std::array<double, 3>>();
  geometry.direction = g[3].cast<std::array<double, 9>>();
  f->input.read.volume.tensors = vectorOf<SymTensor3>(state[4], "the tensors");
  f->input.read.volume.mask = vectorOf<std::uint8_t>(state[5], "the file's mask");
  const py::tuple i = state[6].cast<py::tuple>();
  imaging::TensorFileInfo& info = f->input.read.info;
  info.layout = static_cast<imaging::TensorFileLayout>(i[0].cast<int>());
  info.order = static_cast<imaging::TensorOrder>(i[1].cast<int>());
  info.frame = static_cast<imaging::TensorFrame>(i[2].cast<int>());
  info.frameWasStated = i[3].cast<bool>();
  info.hasMeasurementFrame = i[4].cast<bool>();
  info.measurementFrameLps = i[5].cast<imaging::Matrix3>();
  info.nrrdSpace = i[6].cast<std::string>();
  info.componentsToLps = i[7].cast<imaging::Matrix3>();
  info.componentType = i[8].cast<std::string>();
  info.warnings = i[9].cast<std::vector<std::string>>();
  f->input.mask = vectorOf<std::uint8_t>(state[7], "the mask");
  f->input.maskDescription = state[8].cast<std::string>();
  f->input.warnings = state[9].cast<std::vector<std::string>>();
  const py::tuple given = state[10].cast<py::tuple>();
  f->inputKind = given[0].cast<std::string>();
  f->inputDescription = given[1].cast<std::string>();
  f->layoutDescription = given[2].cast<std::string>();
  f->matrices = given[3].cast<bool>();
  if (f->input.read.volume.tensors.size() != geometry.voxelCount() ||
      (!f->input.mask.empty() && f->input.mask.size() != geometry.voxelCount()))
    throw py::value_error("unpickling stvd: the tensors or the mask do not fill the grid");
  // The metric and the domain, built again as finishField built them.
  py::gil_scoped_release release;
  imaging::MetricFromTensors built = imaging::buildCheckedMetric(f->name, f->input, f->options, &f->frameCheck);
  f->counts = built.counts;
  f->inDomain = std::move(built.inDomain);
  f->metric = RiemannianMetric(std::move(built.metric), &f->inDomain);
  return f;
}

}  // namespace stvd::python
