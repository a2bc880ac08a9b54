#include "stvd/imaging/tensor_arrays.hpp"
#include "stvd/imaging/detail/read_progress.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "stvd/errors.hpp"

namespace stvd::imaging {

GridGeometry gridGeometryFromRasAffine(const std::array<double, 16>& a, const std::array<std::size_t, 3>& size,
                                       const std::optional<std::array<double, 3>>& spacing) {
  for (double x : a)
    if (!std::isfinite(x)) throw std::invalid_argument("the affine has a non-finite entry");
  if (a[12] != 0.0 || a[13] != 0.0 || a[14] != 0.0 || a[15] != 1.0)
    throw std::invalid_argument("the affine's last row is not 0, 0, 0, 1");
  GridGeometry g;
  g.size = size;
  const double flip[3] = {-1.0, -1.0, 1.0};  // RAS -> LPS
  for (int c = 0; c < 3; ++c) {
    const double length = std::sqrt(a[c] * a[c] + a[4 + c] * a[4 + c] + a[8 + c] * a[8 + c]);
    if (!(length > 0.0)) throw std::invalid_argument("column " + std::to_string(c) + " of the affine is zero");
    // NIfTI keeps the spacing as single-precision pixdim, and ITK reads the
    // spacing from there, not from the affine.
    g.spacing[c] = spacing ? (*spacing)[c] : static_cast<double>(static_cast<float>(length));
    for (int r = 0; r < 3; ++r) g.direction[3 * r + c] = flip[r] * (a[4 * r + c] / length);
  }
  for (int r = 0; r < 3; ++r) g.origin[r] = flip[r] * a[4 * r + 3];
  g.validate();
  return g;
}

TensorComponentLayout componentsPerVoxel(const std::array<std::size_t, 3>& size, TensorOrder order) {
  const std::ptrdiff_t nx = static_cast<std::ptrdiff_t>(size[0]), nxy = nx * static_cast<std::ptrdiff_t>(size[1]);
  TensorComponentLayout layout;
  layout.order = order;
  layout.voxelStride = {6, 6 * nx, 6 * nxy};
  for (int q = 0; q < 6; ++q) layout.componentOffset[q] = q;
  return layout;
}

TensorComponentLayout oneVolumePerComponent(const std::array<std::size_t, 3>& size, TensorOrder order) {
  const std::ptrdiff_t nx = static_cast<std::ptrdiff_t>(size[0]), nxy = nx * static_cast<std::ptrdiff_t>(size[1]);
  TensorComponentLayout layout;
  layout.order = order;
  layout.voxelStride = {1, nx, nxy};
  for (int q = 0; q < 6; ++q) layout.componentOffset[q] = q * nxy * static_cast<std::ptrdiff_t>(size[2]);
  return layout;
}

template <class T>
std::vector<SymTensor3> tensorsFromArray(const T* components, const std::array<std::size_t, 3>& size,
                                         const TensorComponentLayout& layout, const Matrix3& frameChange) {
  InterruptScope none(nullptr, "", 0);
  return detail::tensorsFromArray(components, size, layout, frameChange, none, 0);
}

template std::vector<SymTensor3> tensorsFromArray(const float*, const std::array<std::size_t, 3>&,
                                                  const TensorComponentLayout&, const Matrix3&);
template std::vector<SymTensor3> tensorsFromArray(const double*, const std::array<std::size_t, 3>&,
                                                  const TensorComponentLayout&, const Matrix3&);

template <class T>
std::vector<SymTensor3> detail::tensorsFromArray(const T* components, const std::array<std::size_t, 3>& size,
                                                 const TensorComponentLayout& layout, const Matrix3& frameChange,
                                                 InterruptScope& progress, std::uint64_t from) {
  std::vector<SymTensor3> tensors(size[0] * size[1] * size[2]);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  float c[6];
  std::size_t v = 0;
  for (std::size_t k = 0; k < size[2]; ++k)
    for (std::size_t j = 0; j < size[1]; ++j)
      for (std::size_t i = 0; i < size[0]; ++i, ++v) {
        progress.step(from + v);
        const T* voxel = components + static_cast<std::ptrdiff_t>(i) * layout.voxelStride[0] +
                         static_cast<std::ptrdiff_t>(j) * layout.voxelStride[1] +
                         static_cast<std::ptrdiff_t>(k) * layout.voxelStride[2];
        bool finite = true;
        for (int q = 0; q < 6; ++q) {
          const T x = voxel[layout.componentOffset[q]];
          // Beyond float's range a double would become infinite (and its
          // conversion is undefined).
          finite = finite && std::isfinite(x) && std::abs(x) <= std::numeric_limits<float>::max();
          c[q] = finite ? static_cast<float>(x) : 0.f;
        }
        // There is no tensor where a component is not finite (niftilib
        // would have turned a NaN into 0, and the frame change would mix it
        // into some components only).
        tensors[v] = finite ? changeTensorFrame(tensorFromComponents(c, layout.order), frameChange)
                            : SymTensor3{nan, nan, nan, nan, nan, nan};
      }
  return tensors;
}

template std::vector<SymTensor3> detail::tensorsFromArray(const float*, const std::array<std::size_t, 3>&,
                                                          const TensorComponentLayout&, const Matrix3&,
                                                          InterruptScope&, std::uint64_t);
template std::vector<SymTensor3> detail::tensorsFromArray(const double*, const std::array<std::size_t, 3>&,
                                                          const TensorComponentLayout&, const Matrix3&,
                                                          InterruptScope&, std::uint64_t);

TensorOrder resolveTensorOrder(const std::string& name, TensorFileLayout layout,
                               const std::optional<TensorOrder>& stated) {
  if (layout == TensorFileLayout::MrtrixSixVolumes) return stated.value_or(TensorOrder::Mrtrix);
  if (layout == TensorFileLayout::NiftiSixVolumes) {
    if (!stated)
      throw ImageIoError(name, "a NIfTI file with six values per voxel and no SYMMATRIX intent does not say its "
                               "component order; state it with --tensor-order fsl|mrtrix|lower");
    return *stated;
  }
  const TensorOrder fixed = layout == TensorFileLayout::NiftiSymMatrix5D ? TensorOrder::Lower : TensorOrder::Fsl;
  if (stated && *stated != fixed)
    throw ImageIoError(name, "a " + tensorFileLayoutName(layout) + " file has the fixed component order " +
                                 tensorOrderComponents(fixed) + "; the stated order " + tensorOrderName(*stated) +
                                 " contradicts it");
  return fixed;
}

Matrix3 componentFrameToLps(const TensorFileInfo& info, const GridGeometry& geometry) {
  if (info.frame == TensorFrame::Voxel) return voxelAxes(geometry);
  const bool nrrd =
      info.layout == TensorFileLayout::NrrdSymMatrix || info.layout == TensorFileLayout::NrrdMaskedSymMatrix;
  return nrrd ? info.measurementFrameLps : rasToLps();
}

}  // namespace stvd::imaging
