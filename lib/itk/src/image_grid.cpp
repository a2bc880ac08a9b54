#include "stvd/itk/image_grid.hpp"

#include "itk_io_support.hpp"
#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/itk/scalar_image_io.hpp"

namespace stvd::imaging {

GridGeometry readImageGrid(const std::string& path, std::vector<std::string>* warnings) {
  if (isMrtrixImagePath(path)) return readMrtrixImageGrid(path);
  const detail::OpenedImage opened = detail::openImageForReading(path, /*withData=*/false);
  if (warnings) warnings->insert(warnings->end(), opened.screened.warnings.begin(), opened.screened.warnings.end());
  return detail::geometryOf(opened, path);
}

void requireImageOnGrid(const std::string& path, const GridGeometry& reference, const std::string& subject,
                        const std::string& referenceName) {
  requireSameGrid(readImageGrid(path), reference, path, subject, referenceName);
}

ScalarImage readScalarImageOnGrid(const std::string& path, const GridGeometry& reference,
                                  const std::string& subject, const std::string& referenceName,
                                  Interrupter* interrupter) {
  requireImageOnGrid(path, reference, subject, referenceName);
  return readScalarImage(path, interrupter);
}

LabelImage readLabelImageOnGrid(const std::string& path, const GridGeometry& reference, const std::string& subject,
                                const std::string& referenceName, Interrupter* interrupter) {
  requireImageOnGrid(path, reference, subject, referenceName);
  return readLabelImage(path, interrupter);
}

}  // namespace stvd::imaging
