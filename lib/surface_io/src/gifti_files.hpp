// GIfTI documents as the readers of surfaces, values and labels share them.
// Private to surface_io.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "xml_elements.hpp"

namespace stvd::surface_io::detail {

/// One DataArray, decoded: its values row-major as numbers.
struct GiftiArray {
  std::string intent;
  std::vector<std::size_t> dims;
  std::vector<double> values;
  const XmlElement* element = nullptr;  ///< into the document's tree
};

struct GiftiDocument {
  XmlElement root;
  std::vector<GiftiArray> arrays;
  GiftiDocument() = default;
  GiftiDocument(const GiftiDocument&) = delete;  // arrays point into root
  GiftiDocument(GiftiDocument&&) = default;     // a vector's move keeps its elements in place
};

/// The file read and every DataArray decoded. MeshFileError naming the
/// file (and the array) for anything malformed.
GiftiDocument readGifti(const std::string& path);
GiftiArray decodeArray(const XmlElement& dataArray, const std::string& path, std::size_t index);
/// The value of the MetaData entry `name` of `owner`, or empty.
std::string metaDataValue(const XmlElement& owner, const std::string& name);

}  // namespace stvd::surface_io::detail
