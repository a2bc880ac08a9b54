// The XML that GIfTI files are written in, read into a tree of elements:
// elements, attributes, character data (entities and CDATA decoded),
// comments, processing instructions and a DOCTYPE (skipped, never
// followed: no external entity or DTD is read). Private to surface_io.
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace stvd::surface_io::detail {

struct XmlElement {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;
  /// The element's own character data, concatenated (children's excluded).
  std::string text;
  std::vector<XmlElement> children;
  std::size_t line = 0;  ///< where the start tag is, for messages

  /// The attribute's value, or null.
  const std::string* attribute(const std::string& key) const;
  /// The first child of that name, or null.
  const XmlElement* child(const std::string& childName) const;
};

/// The document's root element. Throws MeshFileError "<path>: line N:
/// <problem>" for malformed XML, an element nested deeper than 64 levels,
/// or an unknown entity.
XmlElement parseXml(const std::string& text, const std::string& path);

}  // namespace stvd::surface_io::detail
