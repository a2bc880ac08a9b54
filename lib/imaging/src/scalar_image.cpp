#include "stvd/imaging/scalar_image.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <sstream>
#include <string>

#include "stvd/errors.hpp"

namespace stvd::imaging {

bool hasImageExtension(const std::string& path) {
  std::string lower = path;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  for (const char* ext : {".nii", ".nii.gz", ".nrrd", ".nhdr", ".mif", ".mif.gz"}) {
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

void requireSameGrid(const GridGeometry& image, const GridGeometry& reference, const std::string& imageName,
                     const std::string& subject, const std::string& referenceName) {
  const std::string mismatch = geometryMismatch(image, reference);
  if (!mismatch.empty())
    throw ImageIoError(imageName, subject + " on another grid than " + referenceName + " (" + mismatch + ")");
}

}  // namespace stvd::imaging
