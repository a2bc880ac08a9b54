// FOD images through ITK (NIfTI) and our MRtrix reader; the coefficients'
// checks and layout are fodFieldFromVolumes's (stvd/imaging/fod_field.hpp).
#include "stvd/itk/fod_volume_io.hpp"

#include <string>
#include <vector>

#include "itk_io_support.hpp"
#include "stvd/errors.hpp"
#include "stvd/imaging/mrtrix_image.hpp"

namespace stvd::imaging {
namespace {

ShBasis basisOf(const std::string& path, const std::string& name) {
  const std::optional<ShBasis> basis = parseShBasis(name);
  if (!basis)
    throw ImageIoError(path, "unknown spherical-harmonic basis '" + name + "' (one of " + shBasisNames() + ")");
  return *basis;
}

std::string dimText(const std::vector<std::size_t>& size) {
  std::string dim;
  for (std::size_t s : size) dim += (dim.empty() ? "" : ",") + std::to_string(s);
  return dim;
}

/// An MRtrix image X Y Z N, as dwi2fod and amp2sh write it: MRtrix3's basis
/// in the scanner frame unless stated.
FodField readMrtrixFod(const std::string& path, const FodReadOptions& options) {
  const MrtrixImage image = readMrtrixImage(path);
  const std::vector<std::size_t>& size = image.header.size;
  if (size.size() != 4)
    throw ImageIoError(path, "not an FOD image: spherical-harmonic coefficients lie along a fourth axis "
                             "(dim X,Y,Z,N), this image has dim " + dimText(size));
  const ShBasis basis = options.basis.empty() ? ShBasis::Tournier07 : basisOf(path, options.basis);
  const FodFrame frame = options.frame.value_or(FodFrame::Scanner);
  // The voxel frame of an MRtrix image is its axes as stored (as for
  // tensors: a file mrconvert made from a NIfTI file keeps that file's axes).
  Matrix3 lpsToSh = lpsToFodFrame(frame, image.geometry);
  if (frame == FodFrame::Voxel) {
    const Matrix3 axes = detail::storedVoxelAxes(image.header, image.geometry);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) lpsToSh[3 * r + c] = axes[3 * c + r];
  }
  return fodFieldFromVolumes(path, image.geometry, image.values.data(), image.values.size(), size[3], basis, frame,
                             lpsToSh);
}

}  // namespace

FodField readFodVolume(const std::string& path, const FodReadOptions& options) {
  if (isMrtrixImagePath(path)) return readMrtrixFod(path, options);
  detail::OpenedImage image = detail::openImageForReading(path);
  itk::ImageIOBase::Pointer io = image.io;
  const std::string ioClass = io->GetNameOfClass();
  if (ioClass != "NiftiImageIO")
    throw ImageIoError(path, "unsupported format for an FOD image (" + ioClass + "); use NIfTI or MRtrix (.mif)");
  const unsigned dims = io->GetNumberOfDimensions();
  const unsigned components = io->GetNumberOfComponents();
  if (dims != 4 || components != 1) {
    std::vector<std::size_t> size;
    for (unsigned d = 0; d < dims; ++d) size.push_back(io->GetDimensions(d));
    throw ImageIoError(path, "not an FOD image: spherical-harmonic coefficients lie along a fourth axis "
                             "(4-D X,Y,Z,N, one value per voxel and volume), this image has dim " + dimText(size) +
                             " and " + std::to_string(components) + " component(s) per voxel");
  }
  if (options.basis.empty())
    throw ImageIoError(path, "a NIfTI FOD file does not say its spherical-harmonic basis: state it (one of " +
                                 shBasisNames() + ")");
  const ShBasis basis = basisOf(path, options.basis);
  const std::size_t volumes = io->GetDimensions(3);
  fodDegreeOfVolumes(path, volumes);  // the count checked before the data are read
  const GridGeometry geometry = detail::geometryOf(image, path);
  const FodFrame frame = options.frame.value_or(defaultFodFrame(options.basis));
  const std::vector<float> values = detail::readAllComponents(image, path);
  return fodFieldFromVolumes(path, geometry, values.data(), values.size(), volumes, basis, frame,
                             lpsToFodFrame(frame, geometry));
}

}  // namespace stvd::imaging
