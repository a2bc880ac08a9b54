#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>

#include "itk_io_support.hpp"
#include "written_files.hpp"
#include "stvd/files/output_transaction.hpp"
#include "stvd/itk/image_files.hpp"
#include "stvd/itk/image_io_error.hpp"
#include "stvd/itk/scalar_image.hpp"

namespace stvd::imaging {

ScalarImage readScalarImage(const std::string& path) {
  itk::ImageIOBase::Pointer io = detail::openImageForReading(path);
  const unsigned dims = io->GetNumberOfDimensions();
  if (io->GetNumberOfComponents() != 1)
    throw ImageIoError(path, "not a scalar image: " + std::to_string(io->GetNumberOfComponents()) +
                                 " components per voxel");
  for (unsigned d = 3; d < dims; ++d)
    if (io->GetDimensions(d) != 1)
      throw ImageIoError(path, "not a 3D scalar image: axis " + std::to_string(d + 1) + " has " +
                                   std::to_string(io->GetDimensions(d)) + " samples");
  ScalarImage image;
  image.geometry = detail::geometryOf(*io, path);
  image.values = detail::readAllComponents(*io, path);
  return image;
}

namespace {

void writeScalarImageTo(const std::string& stagingPath, const std::string& path, const GridGeometry& geometry,
                        const std::vector<float>& values) {
  if (values.size() != geometry.voxelCount())
    throw ImageIoError(path, std::to_string(values.size()) + " values for a grid of " +
                                 std::to_string(geometry.voxelCount()) + " voxels");
  checkImageOutputCompanions(path);
  itk::ImageIOBase::Pointer io =
      detail::createFloatWriter(stagingPath, path, geometry, 1, itk::IOPixelEnum::SCALAR);
  detail::writeFloatData(*io, path, values.data());
  detail::checkWrittenImage(stagingPath, path, values);
}

}  // namespace

void writeScalarImage(const std::string& path, const GridGeometry& geometry,
                      const std::vector<float>& values) {
  detail::writeAtomically(
      path, [&](const std::string& staging) { writeScalarImageTo(staging, path, geometry, values); });
}

void writeScalarImage(files::OutputTransaction& outputs, const std::string& path, const GridGeometry& geometry,
                      const std::vector<float>& values) {
  outputs.write(path, [&](const std::string& staging) { writeScalarImageTo(staging, path, geometry, values); });
}

bool hasImageExtension(const std::string& path) {
  std::string lower = path;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* ext : {".nii", ".nii.gz", ".nrrd", ".nhdr"}) {
    const std::size_t n = std::char_traits<char>::length(ext);
    if (lower.size() > n && lower.compare(lower.size() - n, n, ext) == 0) return true;
  }
  return false;
}

std::string geometryMismatch(const GridGeometry& a, const GridGeometry& b) {
  std::ostringstream s;
  if (a.size != b.size) {
    s << "size " << a.size[0] << "x" << a.size[1] << "x" << a.size[2] << " differs from " << b.size[0] << "x"
      << b.size[1] << "x" << b.size[2];
    return s.str();
  }
  for (int i = 0; i < 3; ++i)
    if (std::abs(a.spacing[i] - b.spacing[i]) > 1e-4 * std::max(a.spacing[i], b.spacing[i])) {
      s << "spacing " << a.spacing[0] << "," << a.spacing[1] << "," << a.spacing[2] << " mm differs from "
        << b.spacing[0] << "," << b.spacing[1] << "," << b.spacing[2] << " mm";
      return s.str();
    }
  const double minSpacing = std::min({a.spacing[0], a.spacing[1], a.spacing[2]});
  for (int i = 0; i < 3; ++i)
    if (std::abs(a.origin[i] - b.origin[i]) > 1e-3 * minSpacing) {
      s << "origin (LPS) " << a.origin[0] << "," << a.origin[1] << "," << a.origin[2] << " mm differs from "
        << b.origin[0] << "," << b.origin[1] << "," << b.origin[2] << " mm";
      return s.str();
    }
  for (int i = 0; i < 9; ++i)
    if (std::abs(a.direction[i] - b.direction[i]) > 1e-4) return "direction cosines differ";
  return {};
}

}  // namespace stvd::imaging
