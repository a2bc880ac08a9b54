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

std::string dimText(const std::vector<std::size_t>& size) {
  std::string dim;
  for (std::size_t s : size) dim += (dim.empty() ? "" : ",") + std::to_string(s);
  return dim;
}

}  // namespace

FodField readFodVolume(const std::string& path, const FodReadOptions& options) {
  if (isMrtrixImagePath(path)) return readMrtrixFodVolume(path, options);
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
  const ShBasis basis = shBasisOfFile(path, options.basis);
  const std::size_t volumes = io->GetDimensions(3);
  fodDegreeOfVolumes(path, volumes);  // the count checked before the data are read
  const GridGeometry geometry = detail::geometryOf(image, path);
  const FodFrame frame = options.frame.value_or(defaultFodFrame(options.basis));
  const std::vector<float> values = detail::readAllComponents(image, path);
  return fodFieldFromVolumes(path, geometry, values.data(), values.size(), volumes, basis, frame,
                             lpsToFodFrame(frame, geometry));
}

}  // namespace stvd::imaging
