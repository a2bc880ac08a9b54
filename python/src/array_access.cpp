#include "array_access.hpp"

#include <cmath>
#include <sstream>
#include <type_traits>

#include "stvd/imaging/label_values.hpp"
#include "stvd/imaging/streamline_io.hpp"

namespace stvd::python {

py::array numericArray(const py::handle& object, const std::string& name) {
  py::module_ numpy = py::module_::import("numpy");
  // A masked array's mask would be dropped without a word here: its masked
  // values would count as data. Tensors, masks and label images split it
  // first (splitMaskedArray); what reaches this point has no use for one.
  if (py::isinstance(object, numpy.attr("ma").attr("MaskedArray")))
    throw py::type_error(name + ": a masked array, whose mask means nothing here (masks are honoured in tensors, "
                                "mask= and label images); give plain values");
  py::array array = py::array::ensure(object);
  if (!array) throw py::type_error(name + ": expected a NumPy array (or a nested list of numbers), got " +
                                   std::string(py::str(py::type::of(object).attr("__name__"))));
  const char kind = array.dtype().kind();
  const std::string dtype = py::str(array.dtype());
  if (kind == 'c')
    throw py::type_error(name + ": expected real numbers, got complex values (dtype " + dtype + ")");
  if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f')
    throw py::type_error(name + ": expected numbers, got an array of dtype " + dtype);
  // Only the types read exactly: booleans, integers of 1 to 8 bytes,
  // float16 (converted to float32, exactly), float32 and float64. Extended
  // precision (numpy.longdouble, 10 to 16 bytes) is refused: read as
  // float64 through its strides it would be other numbers, and rounded to
  // float64 a mask or label can change (1e-5000 is not 0 in long double).
  const py::ssize_t item = array.itemsize();
  if ((kind == 'f' && item != 2 && item != 4 && item != 8) || ((kind == 'i' || kind == 'u') && item > 8) ||
      (kind == 'b' && item != 1))
    throw py::type_error(name + ": values of dtype " + dtype + " (" + std::to_string(item) +
                         " bytes) are not read exactly; convert them to float64, float32 or an integer type "
                         "first (array.astype(numpy.float64))");
  // Half precision has no C++ type here, and a foreign byte order no direct
  // reading: both are converted once to a native type.
  if (kind == 'f' && item == 2) array = array.attr("astype")(numpy.attr("float32"));
  if (array.dtype().byteorder() == '>') array = array.attr("astype")(array.dtype().attr("newbyteorder")("="));
  // Elements are read through typed pointers: strides that are not a
  // multiple of the element size (a field of a structured array) and
  // unaligned memory (a buffer at an odd offset) are copied first.
  bool copy = !(py::detail::array_proxy(array.ptr())->flags & py::detail::npy_api::NPY_ARRAY_ALIGNED_);
  for (py::ssize_t d = 0; d < array.ndim(); ++d)
    if (array.strides(d) % array.itemsize() != 0) copy = true;
  if (copy) array = numpy.attr("ascontiguousarray")(array);
  return array;
}

MaskedSplit splitMaskedArray(const py::handle& object) {
  py::module_ ma = py::module_::import("numpy").attr("ma");
  if (!py::isinstance(object, ma.attr("MaskedArray")))
    return {py::reinterpret_borrow<py::object>(object), py::none()};
  // getmaskarray gives a full bool array even for numpy.ma.nomask; the
  // values under the mask may be anything (NaN, garbage), so they are
  // replaced, not read.
  py::object masked = ma.attr("getmaskarray")(object);
  py::object values = ma.attr("filled")(object, 0);
  if (!masked.attr("any")().cast<bool>()) masked = py::none();
  return {values, masked};
}

std::string shapeText(const py::array& array) {
  std::ostringstream s;
  s << "(";
  for (py::ssize_t d = 0; d < array.ndim(); ++d) s << (d ? ", " : "") << array.shape(d);
  if (array.ndim() == 1) s << ",";
  s << ")";
  return s.str();
}

void requireDimensions(const py::array& array, int ndim, const std::string& name, const std::string& expected) {
  if (array.ndim() != ndim)
    throw py::value_error(name + ": expected an array of shape " + expected + ", got shape " + shapeText(array));
}

void requireFloatingPoint(const py::array& array, const std::string& name) {
  if (array.dtype().kind() != 'f')
    throw py::type_error(name + ": expected float32 or float64 values, got dtype " +
                         std::string(py::str(array.dtype())));
}

namespace {

/// out[v] = convert(element, v) for the elements of a 3D array in the
/// library's voxel order, through the array's strides, without the GIL.
template <class T, class Out, class Convert>
void copyVoxels(const py::array& array, std::vector<Out>& out, Convert convert) {
  const T* data = static_cast<const T*>(array.data());
  const py::ssize_t s0 = array.strides(0) / array.itemsize(), s1 = array.strides(1) / array.itemsize(),
                    s2 = array.strides(2) / array.itemsize();
  const py::ssize_t n0 = array.shape(0), n1 = array.shape(1), n2 = array.shape(2);
  py::gil_scoped_release release;
  std::size_t v = 0;
  for (py::ssize_t k = 0; k < n2; ++k)
    for (py::ssize_t j = 0; j < n1; ++j)
      for (py::ssize_t i = 0; i < n0; ++i, ++v) out[v] = convert(data[i * s0 + j * s1 + k * s2], v);
}

/// Calls f(T{}) with T the element type of a numeric array.
template <class F>
void withElementType(const py::array& array, F&& f) {
  const char kind = array.dtype().kind();
  const auto size = array.itemsize();
  if (kind == 'f')
    size == 4 ? f(float{}) : f(double{});
  else if (kind == 'b' || (kind == 'u' && size == 1))
    f(std::uint8_t{});
  else if (kind == 'u')
    size == 2 ? f(std::uint16_t{}) : size == 4 ? f(std::uint32_t{}) : f(std::uint64_t{});
  else
    size == 1 ? f(std::int8_t{}) : size == 2 ? f(std::int16_t{}) : size == 4 ? f(std::int32_t{}) : f(std::int64_t{});
}

}  // namespace

std::vector<float> voxelValues(const py::array& array) {
  std::vector<float> out(static_cast<std::size_t>(array.size()));
  withElementType(array, [&](auto type) {
    using T = decltype(type);
    copyVoxels<T>(array, out, [](T x, std::size_t) { return static_cast<float>(x); });
  });
  return out;
}

std::vector<std::int64_t> voxelLabels(const py::array& array, const std::string& name, const GridGeometry& geometry) {
  std::vector<std::int64_t> out(static_cast<std::size_t>(array.size()));
  withElementType(array, [&](auto type) {
    using T = decltype(type);
    copyVoxels<T>(array, out, [&](T x, std::size_t v) -> std::int64_t {
      if constexpr (std::is_floating_point_v<T>)
        return imaging::labelOfReal(static_cast<double>(x), name, geometry, v);
      else if constexpr (std::is_same_v<T, std::uint64_t>)
        return imaging::labelOfUnsigned64(x, name, geometry, v);
      else
        return static_cast<std::int64_t>(x);
    });
  });
  return out;
}

std::vector<Vec3d> pointRows(const py::handle& object, const std::string& name) {
  const py::array array = numericArray(object, name);
  if (array.ndim() != 2 || array.shape(1) != 3)
    throw py::value_error(name + ": expected an array of shape (N, 3), got shape " + shapeText(array));
  const py::array_t<double> values = array.attr("astype")("float64");
  const auto r = values.unchecked<2>();
  std::vector<Vec3d> points(static_cast<std::size_t>(r.shape(0)));
  for (py::ssize_t n = 0; n < r.shape(0); ++n) {
    points[n] = {r(n, 0), r(n, 1), r(n, 2)};
    if (!std::isfinite(points[n].x) || !std::isfinite(points[n].y) || !std::isfinite(points[n].z))
      throw py::value_error(name + ": row " + std::to_string(n) + " is not finite");
  }
  return points;
}

std::array<double, 16> affineOf(const py::handle& object, const std::string& name) {
  const py::array array = numericArray(object, name);
  if (array.ndim() != 2 || array.shape(0) != 4 || array.shape(1) != 4)
    throw py::value_error(name + ": expected a 4x4 array (voxel index to RAS millimetres), got shape " +
                          shapeText(array));
  const py::array_t<double> values = array.attr("astype")("float64");
  const auto r = values.unchecked<2>();
  std::array<double, 16> affine{};
  for (int row = 0; row < 4; ++row)
    for (int column = 0; column < 4; ++column) affine[4 * row + column] = r(row, column);
  return affine;
}

py::array_t<double> affineArray(const GridGeometry& g) {
  const std::array<double, 16> m = imaging::voxelToRas(g);
  py::array_t<double> a({4, 4});
  auto w = a.mutable_unchecked<2>();
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) w(r, c) = m[4 * r + c];
  return a;
}

py::array_t<double> newFortranArray(const std::array<std::size_t, 3>& shape) {
  return py::array_t<double, py::array::f_style>({shape[0], shape[1], shape[2]});
}

py::array_t<float> newFortranFloatArray(const std::array<std::size_t, 3>& shape) {
  return py::array_t<float, py::array::f_style>({shape[0], shape[1], shape[2]});
}

}  // namespace stvd::python
