// Bytes as the neuroimaging surface formats encode them: base64 (GIfTI),
// zlib or gzip streams (GIfTI's GZipBase64Binary, .mgz), and numbers of
// either byte order. Private to surface_io.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

namespace stvd::surface_io::detail {

/// Decodes base64, skipping white space; false on any other character
/// outside the alphabet or bad padding.
bool decodeBase64(const std::string& text, std::string& bytes);
std::string encodeBase64(const std::string& bytes);

/// Deflates `bytes` into a zlib stream (what GIfTI's GZipBase64Binary holds
/// before base64, as NiBabel and Connectome Workbench write it), at zlib's
/// default level; the same bytes for the same input (a zlib header has no
/// time stamp). False only when zlib fails (out of memory).
bool deflateZlib(const std::string& bytes, std::string& out);

/// Inflates a zlib or gzip stream (told apart by its header) into exactly
/// `expectedBytes` bytes. Returns an empty text on success, or the problem:
/// "not a zlib or gzip stream", "the compressed data ends early", "the
/// data inflate to more than N bytes". Never holds more than
/// `expectedBytes` bytes of output.
std::string inflateExactly(const std::string& compressed, std::size_t expectedBytes, std::string& out);

/// Inflates the first `maxBytes` bytes of a zlib or gzip stream (less when
/// it ends before); what follows is not read. Returns an empty text on
/// success, or the problem.
std::string inflatePrefix(const std::string& compressed, std::size_t maxBytes, std::string& out);

inline bool hostIsLittleEndian() {
  const std::uint16_t one = 1;
  unsigned char b;
  std::memcpy(&b, &one, 1);
  return b == 1;
}

/// A number of type T at `p`, stored big-endian (`big`) or little-endian.
template <class T>
T loadNumber(const char* p, bool big) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, p, sizeof(T));
  if (big == hostIsLittleEndian())
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) {
      const unsigned char t = b[i];
      b[i] = b[sizeof(T) - 1 - i];
      b[sizeof(T) - 1 - i] = t;
    }
  T value;
  std::memcpy(&value, b, sizeof(T));
  return value;
}

/// Appends `value` in the byte order asked for.
template <class T>
void storeNumber(std::string& out, T value, bool big) {
  unsigned char b[sizeof(T)];
  std::memcpy(b, &value, sizeof(T));
  if (big == hostIsLittleEndian())
    for (std::size_t i = 0; i < sizeof(T) / 2; ++i) {
      const unsigned char t = b[i];
      b[i] = b[sizeof(T) - 1 - i];
      b[sizeof(T) - 1 - i] = t;
    }
  out.append(reinterpret_cast<const char*>(b), sizeof(T));
}

}  // namespace stvd::surface_io::detail
