// Reading NumPy arrays as the library's inputs: checks of dimensions and
// element types with one-line messages (TypeError, ValueError), and element
// access through the array's own strides, so that an input is read once,
// in place, whatever its memory order.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "stvd/voxel_grid/grid_geometry.hpp"
#include "stvd/types.hpp"

namespace stvd::python {

namespace py = pybind11;

/// `object` as a NumPy array (no copy when it is one already) in native
/// byte order. TypeError naming `name` when it is not numeric (bool,
/// integer or floating point), or a masked array: where a mask means
/// something (tensors, masks, label images) the caller splits it first
/// (splitMaskedArray); elsewhere (an affine, points, a mesh) it does not.
py::array numericArray(const py::handle& object, const std::string& name);

/// A numpy.ma masked array split into its values and its mask: `values` has
/// every masked element replaced by 0 (so it reads as "outside" in a mask,
/// "no region" in a label image, and a zero tensor that the voxel's mask
/// leaves out anyway), and `masked` is a bool array of the same shape, or
/// None when `object` is no masked array or nothing in it is masked.
/// Anything else is returned as it is in `values`.
struct MaskedSplit {
  py::object values;
  py::object masked;
};
MaskedSplit splitMaskedArray(const py::handle& object);

/// "(112, 112, 32, 6)".
std::string shapeText(const py::array& array);

/// Throws ValueError naming `name` unless the array has `ndim` dimensions.
void requireDimensions(const py::array& array, int ndim, const std::string& name, const std::string& expected);

/// Throws TypeError naming `name` unless the array holds float32 or float64.
void requireFloatingPoint(const py::array& array, const std::string& name);

/// A view of an array's memory that can be read without the GIL: the
/// caller keeps the array alive. Strides are in elements.
template <class T>
struct StridedView {
  const T* data = nullptr;
  std::vector<std::ptrdiff_t> stride;
  std::vector<std::size_t> shape;
};

/// The view of a float32 (T = float) or float64 (T = double) array; the
/// array's strides must be multiples of its element size (numericArray
/// ensures it).
template <class T>
StridedView<T> viewOf(const py::array& array) {
  StridedView<T> view;
  view.data = static_cast<const T*>(array.data());
  for (py::ssize_t d = 0; d < array.ndim(); ++d) {
    view.stride.push_back(array.strides(d) / static_cast<py::ssize_t>(sizeof(T)));
    view.shape.push_back(static_cast<std::size_t>(array.shape(d)));
  }
  return view;
}

/// Calls f(view) with a StridedView<float> or StridedView<double> of a
/// float32 or float64 array.
template <class F>
decltype(auto) withFloatView(const py::array& array, F&& f) {
  if (array.dtype().itemsize() == 4) return f(viewOf<float>(array));
  return f(viewOf<double>(array));
}

/// The values of a 3D numeric array of any element type as float, in the
/// library's voxel order (linear index i + nx*(j + ny*k)). Releases the GIL
/// while it copies.
std::vector<float> voxelValues(const py::array& array);

/// The values of a 3D numeric array as labels, by the rules of the label
/// image reader (stvd/imaging/label_values.hpp): integers exactly, floating-point
/// values only when they are integers (NaN: no label). ImageIoError naming
/// `name` and the voxel of `geometry` otherwise. Releases the GIL.
std::vector<std::int64_t> voxelLabels(const py::array& array, const std::string& name, const GridGeometry& geometry);

/// An (N, 3) float array as points (any float or integer type).
std::vector<Vec3d> pointRows(const py::handle& object, const std::string& name);

/// A 4x4 float array as 16 doubles, row-major.
std::array<double, 16> affineOf(const py::handle& object, const std::string& name);
/// The grid's voxel-to-RAS affine as a 4x4 float64 array (NiBabel's).
py::array_t<double> affineArray(const GridGeometry& g);

/// A new float64 or float32 NumPy array of the given shape in Fortran order
/// (first index fastest), the library's voxel order.
py::array_t<double> newFortranArray(const std::array<std::size_t, 3>& shape);
py::array_t<float> newFortranFloatArray(const std::array<std::size_t, 3>& shape);

/// A read-only NumPy view of `data` with the given shape in Fortran order,
/// which keeps `owner` alive.
template <class T>
py::array fortranView(const T* data, const std::vector<std::size_t>& shape, py::handle owner) {
  std::vector<py::ssize_t> strides;
  py::ssize_t step = sizeof(T);
  for (std::size_t extent : shape) {
    strides.push_back(step);
    step *= static_cast<py::ssize_t>(extent);
  }
  std::vector<py::ssize_t> dims(shape.begin(), shape.end());
  py::array view(py::dtype::of<T>(), dims, strides, data, owner);
  py::detail::array_proxy(view.ptr())->flags &= ~py::detail::npy_api::NPY_ARRAY_WRITEABLE_;
  return view;
}

}  // namespace stvd::python
