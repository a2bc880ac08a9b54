// A fibre orientation distribution (FOD) image in memory: spherical-harmonic
// coefficients per voxel, with their basis and the frame of their axes
// stated, and the FOD's amplitude along a direction of stvd's physical frame
// (LPS). Reading FOD files is stvd/itk/fod_volume_io.hpp; docs/fod.md.
#pragma once

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "stvd/imaging/spherical_harmonics.hpp"
#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/types.hpp"
#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

/// The frame whose x, y, z axes the spherical harmonics' angles are taken
/// in (theta from z, phi from x towards y).
enum class FodFrame {
  /// The scanner's right-anterior-superior axes, those of the image's
  /// transform (MRtrix3: dwi2fod and amp2sh fit the gradient directions of
  /// the dw_scheme, which are scanner RAS, whatever the image's axes).
  Scanner,
  /// The image's index axes i, j, k as stored (DIPY: its models fit the
  /// b-vectors as given, which follow the voxel array, and its trackers step
  /// in voxel coordinates before the affine is applied).
  Voxel,
};

/// "scanner" (alias "world") or "voxel"; nullopt otherwise.
std::optional<FodFrame> parseFodFrame(const std::string& name);
std::string fodFrameName(FodFrame frame);

/// The frame a basis's own software stores it in when the file does not
/// say: Scanner for "mrtrix3", Voxel for DIPY's names (every other one).
FodFrame defaultFodFrame(const std::string& basisName);

/// Spherical-harmonic coefficients on a grid.
struct FodField {
  GridGeometry geometry;  ///< LPS, as every grid in stvd
  int lmax = 0;
  ShBasis basis = ShBasis::Tournier07;
  FodFrame frame = FodFrame::Scanner;
  /// Row-major 3x3: a direction's components in the SH frame are this
  /// matrix times its LPS components (rows: the SH frame's axes in LPS).
  Matrix3 lpsToShFrame{1, 0, 0, 0, 1, 0, 0, 0, 1};
  /// voxel v's coefficients are coefficients[v * coefficientCount() + j],
  /// j = l(l+1)/2 + m (spherical_harmonics.hpp); finite.
  std::vector<float> coefficients;

  int coefficientCount() const { return shCoefficientCount(lmax); }
  /// The coefficients of voxel v.
  const float* voxelCoefficients(std::size_t v) const {
    return coefficients.data() + v * static_cast<std::size_t>(coefficientCount());
  }
  /// The direction (LPS, any non-zero length) in the SH frame, unit length.
  Vec3d toShFrame(const Vec3d& directionLps) const;
  /// The FOD's amplitude at voxel v along the direction (LPS, any non-zero
  /// length; an FOD is antipodally symmetric, even degrees only), in double.
  double amplitude(std::size_t v, const Vec3d& directionLps) const;
};

/// The matrix FodField::lpsToShFrame for a frame and grid: diag(-1, -1, 1)
/// for Scanner (RAS <-> LPS), the transpose of the grid's unit index axes for
/// Voxel.
Matrix3 lpsToFodFrame(FodFrame frame, const GridGeometry& geometry);

/// The lmax of an FOD image of `volumes` coefficients per voxel (1, 6, 15,
/// 28, 45, 66 or 91: lmax 0 to 12). Throws ImageIoError naming `name` and
/// the count for any other.
int fodDegreeOfVolumes(const std::string& name, std::size_t volumes);

/// A field from values stored one volume after another (volume j holds
/// coefficient j of every voxel, voxels in linear order i fastest), as
/// 4-D images store them. `name` (the file) is used in messages. Throws
/// ImageIoError naming it, in one line: a volume count that is no even
/// lmax's from 0 to 12 (1, 6, 15, 28, 45, 66, 91), a value count that does
/// not match the grid, a coefficient that is NaN or infinite (with its
/// voxel).
FodField fodFieldFromVolumes(const std::string& name, const GridGeometry& geometry, const float* values,
                             std::size_t valueCount, std::size_t volumes, ShBasis basis, FodFrame frame,
                             const Matrix3& lpsToShFrame);

struct FodReadOptions {
  /// The basis by name (parseShBasis). Empty: tournier07 for MRtrix images
  /// (MRtrix3's basis); a NIfTI file must have it stated.
  std::string basis;
  /// The frame of the coefficients. Unset: scanner for MRtrix images;
  /// for NIfTI defaultFodFrame(basis): scanner for "mrtrix3", voxel for
  /// DIPY's basis names.
  std::optional<FodFrame> frame;
};

/// The basis of that name (parseShBasis), or an ImageIoError naming the
/// file and the accepted names.
ShBasis shBasisOfFile(const std::string& path, const std::string& name);

/// Reads an FOD image from a .mif, .mif.gz or .mih file (X Y Z N) with our
/// own MRtrix reader (no ITK; stvd/itk/fod_volume_io.hpp reads NIfTI too):
/// MRtrix3's basis (tournier07) in the scanner frame unless stated; the
/// voxel frame of an MRtrix image is its axes as stored
/// (mrtrixStoredVoxelAxes). Throws ImageIoError with one line naming the
/// file, as fodFieldFromVolumes and readMrtrixImage do, and for an unknown
/// basis name or an image that is not 4-D.
FodField readMrtrixFodVolume(const std::string& path, const FodReadOptions& options = {});

}  // namespace stvd::imaging
