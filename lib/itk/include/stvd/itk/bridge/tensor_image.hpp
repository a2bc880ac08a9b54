// ITK tensor images as stvd's tensor input: the grid of the image's
// buffered region and its tensors brought into the LPS frame, from a frame
// the caller states. Header-only; includes ITK headers (link ITK yourself:
// find_package(ITK), include(${ITK_USE_FILE})).
//
// Why the frame is a required argument: ITK never rotates a tensor's
// components, neither when it reads a file nor afterwards, and an
// itk::Image does not say in which frame they are given. DIPY and FSL fit
// tensors along the image's index axes, MRtrix in scanner RAS, teem in the
// NRRD measurement frame; a wrong guess gives wrong distances with no
// error. So there is no default.
#pragma once

#include <itkDiffusionTensor3D.h>
#include <itkImage.h>
#include <itkMetaDataObject.h>
#include <itkSymmetricSecondRankTensor.h>

#include <array>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "stvd/errors.hpp"
#include "stvd/imaging/scalar_image.hpp"
#include "stvd/imaging/tensor_arrays.hpp"
#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/imaging/tensor_input.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

/// The frame in which the six components of an ITK tensor image are given.
class ItkTensorFrame {
 public:
  /// Along the image's index axes (i, j, k): tensors fitted from b-vectors
  /// in FSL's convention (FSL dtifit, DIPY). The tool's `--tensor-frame
  /// voxel`.
  static ItkTensorFrame indexAxes() { return ItkTensorFrame(Kind::IndexAxes, identity(), "index axes"); }
  /// ITK's physical frame, LPS: tensors made by ITK filters from gradients
  /// given in physical space. Kept as they are.
  static ItkTensorFrame lps() { return ItkTensorFrame(Kind::Matrix, identity(), "LPS"); }
  /// Scanner RAS, the world frame of NIfTI and MRtrix images (MRtrix's
  /// dwi2tensor): F T F with F = diag(-1, -1, 1). The tool's
  /// `--tensor-frame world` for NIfTI and MRtrix files.
  static ItkTensorFrame ras() { return ItkTensorFrame(Kind::Matrix, rasToLps(), "RAS"); }
  /// The NRRD measurement frame, as ITK's NRRD reader leaves it in the
  /// image's meta-data dictionary: "NRRD_measurement frame" holds one
  /// vector per frame axis, in NRRD space coordinates — entry [c] is the
  /// c-th axis of the frame, that is column c of the matrix M with
  /// T_space = M T M^T (the NRRD header's "measurement frame: (..) (..)
  /// (..)" lists the same vectors in the same order). "NRRD_space" says
  /// which space: left-posterior-superior (kept) or right-anterior-superior
  /// (flipped to LPS). A NRRD file without a measurement frame has its
  /// components along the space's axes. The tool's `--tensor-frame world`
  /// for NRRD files (its default there). Throws InputError when the
  /// dictionary has no "NRRD_space" (the image was not read from NRRD) or
  /// names another space.
  static ItkTensorFrame nrrdMeasurementFrame(const itk::MetaDataDictionary& dictionary) {
    std::string space;
    if (!itk::ExposeMetaData<std::string>(dictionary, "NRRD_space", space))
      throw InputError("the tensor image's meta-data have no NRRD_space: it was not read from a NRRD file, so it "
                       "has no measurement frame (state the frame: indexAxes(), lps() or ras())");
    Matrix3 spaceToLps = identity();
    if (space == "right-anterior-superior")
      spaceToLps = rasToLps();
    else if (space != "left-posterior-superior")
      throw InputError("the tensor image's NRRD space is '" + space +
                       "': only left-posterior-superior and right-anterior-superior are supported");
    Matrix3 frame = identity();
    std::vector<std::vector<double>> axes;
    if (itk::ExposeMetaData<std::vector<std::vector<double>>>(dictionary, "NRRD_measurement frame", axes)) {
      if (axes.size() != 3 || axes[0].size() != 3 || axes[1].size() != 3 || axes[2].size() != 3)
        throw InputError("the tensor image's NRRD measurement frame is not 3 x 3");
      for (int c = 0; c < 3; ++c)
        for (int r = 0; r < 3; ++r) frame[3 * r + c] = axes[c][r];
    }
    return ItkTensorFrame(Kind::Matrix, multiply(spaceToLps, frame), "NRRD measurement frame (" + space + ")");
  }
  /// Any frame: `axesInLps` holds the frame's axes as columns, in LPS
  /// coordinates (T_LPS = M T M^T). `name` appears in messages.
  static ItkTensorFrame fromMatrix(const Matrix3& axesInLps, std::string name) {
    return ItkTensorFrame(Kind::Matrix, axesInLps, std::move(name));
  }

  /// M with T_LPS = M T M^T, for tensors on `grid`.
  Matrix3 toLps(const GridGeometry& grid) const { return kind_ == Kind::IndexAxes ? voxelAxes(grid) : matrix_; }
  /// The tool's TensorFrame this frame corresponds to, for reports.
  TensorFrame tensorFrame() const { return kind_ == Kind::IndexAxes ? TensorFrame::Voxel : TensorFrame::World; }
  const std::string& name() const { return name_; }

 private:
  enum class Kind { IndexAxes, Matrix };
  ItkTensorFrame(Kind kind, const Matrix3& matrix, std::string name)
      : kind_(kind), matrix_(matrix), name_(std::move(name)) {}
  static Matrix3 identity() { return {1, 0, 0, 0, 1, 0, 0, 0, 1}; }
  Kind kind_;
  Matrix3 matrix_;
  std::string name_;
};

/// The grid of an ITK image's buffered region: its size, the spacing and
/// direction cosines, and as origin the physical point of the region's
/// first index (not the image's origin, when the region does not start at
/// index 0). In LPS millimetres, as ITK holds it. Vertex (i, j, k) of a
/// domain on this grid is the image's index region.GetIndex() + (i, j, k).
template <class TImage>
GridGeometry gridGeometryOf(const TImage& image) {
  static_assert(TImage::ImageDimension == 3, "stvd's voxel grids are 3D");
  const auto region = image.GetBufferedRegion();
  GridGeometry g;
  typename TImage::PointType first;
  image.TransformIndexToPhysicalPoint(region.GetIndex(), first);
  for (unsigned a = 0; a < 3; ++a) {
    g.size[a] = region.GetSize(a);
    g.spacing[a] = image.GetSpacing()[a];
    g.origin[a] = first[a];
    for (unsigned c = 0; c < 3; ++c) g.direction[3 * a + c] = image.GetDirection()(a, c);
  }
  return g;
}

namespace detail {
template <class Pixel>
struct ItkTensorPixel : std::false_type {};
template <class T>
struct ItkTensorPixel<itk::DiffusionTensor3D<T>> : std::true_type {
  using Component = T;
};
template <class T>
struct ItkTensorPixel<itk::SymmetricSecondRankTensor<T, 3>> : std::true_type {
  using Component = T;
};
}  // namespace detail

/// The tensor input of an ITK image of itk::DiffusionTensor3D<T> or
/// itk::SymmetricSecondRankTensor<T, 3> (T float or double) with its
/// components in `frame`: the grid of its buffered region (gridGeometryOf)
/// and one tensor per voxel in LPS. ITK keeps a tensor's components in the
/// order xx, xy, xz, yy, yz, zz of its own frame (upper triangle, row by
/// row); a voxel with a non-finite component has no tensor (outside the
/// domain), as in a file. `name` names the image in messages. The same
/// conversion as the file readers' (tensorsFromArray), so an image read by
/// ITK gives exactly the tensors `stvd distance` reads from the file.
template <class TImage>
TensorInput tensorInputFromItkImage(const TImage& image, const ItkTensorFrame& frame,
                                    const std::string& name = "the ITK tensor image") {
  using Pixel = typename TImage::PixelType;
  static_assert(detail::ItkTensorPixel<Pixel>::value,
                "a tensor image has pixels itk::DiffusionTensor3D<T> or itk::SymmetricSecondRankTensor<T, 3>");
  using T = typename detail::ItkTensorPixel<Pixel>::Component;
  static_assert(std::is_same<T, float>::value || std::is_same<T, double>::value, "float or double components");
  static_assert(sizeof(Pixel) == 6 * sizeof(T), "six components per pixel, packed");
  TensorReadResult read;
  read.volume.geometry = gridGeometryOf(image);
  const GridGeometry& g = read.volume.geometry;
  if (g.voxelCount() == 0 || image.GetBufferPointer() == nullptr)
    throw InputError(name + ": the image holds no pixels (was its pipeline updated?)");
  read.info.layout = TensorFileLayout::NrrdSymMatrix;  // six per voxel, xx xy xz yy yz zz
  read.info.order = TensorOrder::Fsl;
  read.info.frame = frame.tensorFrame();
  read.info.frameWasStated = true;
  read.info.componentsToLps = frame.toLps(g);
  read.info.componentType = std::is_same<T, float>::value ? "float" : "double";
  read.volume.tensors = tensorsFromArray(reinterpret_cast<const T*>(image.GetBufferPointer()), g.size,
                                         componentsPerVoxel(g.size, TensorOrder::Fsl), read.info.componentsToLps);
  return tensorInputOf(std::move(read), name);
}

/// A scalar ITK image (a mask, an FA map) as stvd's ScalarImage: the grid
/// of its buffered region, its values as float.
template <class TImage>
ScalarImage scalarImageFromItkImage(const TImage& image) {
  ScalarImage s;
  s.geometry = gridGeometryOf(image);
  s.values.resize(s.geometry.voxelCount());
  const auto* p = image.GetBufferPointer();
  for (std::size_t v = 0; v < s.values.size(); ++v) s.values[v] = static_cast<float>(p[v]);
  return s;
}

/// Restricts `input` to the voxels where the ITK image `mask` is neither zero
/// nor NaN. Throws ImageIoError naming `maskName` when its grid (buffered
/// region) differs from the tensors'.
template <class TMaskImage>
void addItkMask(TensorInput& input, const TMaskImage& mask, const std::string& maskName = "the ITK mask image",
                const std::string& inputName = "the ITK tensor image") {
  addMask(input, scalarImageFromItkImage(mask), maskName, inputName);
}

}  // namespace stvd::imaging
