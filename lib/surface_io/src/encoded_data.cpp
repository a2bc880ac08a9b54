#include "encoded_data.hpp"

#include <zlib.h>

#include <algorithm>
#include <array>

namespace stvd::surface_io::detail {

bool decodeBase64(const std::string& text, std::string& bytes) {
  static const auto table = [] {
    std::array<signed char, 256> t{};
    t.fill(-1);
    const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int i = 0; i < 64; ++i) t[static_cast<unsigned char>(alphabet[i])] = static_cast<signed char>(i);
    return t;
  }();
  bytes.assign(text.size() / 4 * 3 + 3, '\0');
  std::size_t out = 0;
  std::uint32_t buffer = 0;
  int bits = 0, padding = 0;
  for (const char c : text) {
    const signed char v = table[static_cast<unsigned char>(c)];
    if (v >= 0 && padding == 0) {
      buffer = (buffer << 6) | static_cast<std::uint32_t>(v);
      bits += 6;
      if (bits >= 8) {
        bits -= 8;
        bytes[out++] = static_cast<char>((buffer >> bits) & 0xFF);
      }
      continue;
    }
    if (c == ' ' || c == '\n' || c == '\r' || c == '\t') continue;
    if (c == '=') {
      ++padding;
      continue;
    }
    return false;  // a character outside the alphabet, or data after '='
  }
  bytes.resize(out);
  return padding <= 2 && bits < 6;
}

std::string encodeBase64(const std::string& bytes) {
  const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const std::uint32_t v = (static_cast<unsigned char>(bytes[i]) << 16) |
                            (static_cast<unsigned char>(bytes[i + 1]) << 8) | static_cast<unsigned char>(bytes[i + 2]);
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += alphabet[(v >> 6) & 63];
    out += alphabet[v & 63];
  }
  if (i < bytes.size()) {
    std::uint32_t v = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += alphabet[(v >> 18) & 63];
    out += alphabet[(v >> 12) & 63];
    out += i + 1 < bytes.size() ? alphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

bool deflateZlib(const std::string& bytes, std::string& out) {
  uLongf size = compressBound(static_cast<uLong>(bytes.size()));
  out.assign(size, '\0');
  if (compress2(reinterpret_cast<Bytef*>(out.data()), &size, reinterpret_cast<const Bytef*>(bytes.data()),
                static_cast<uLong>(bytes.size()), Z_DEFAULT_COMPRESSION) != Z_OK)
    return false;
  out.resize(size);
  return true;
}

std::string inflateExactly(const std::string& compressed, std::size_t expectedBytes, std::string& out) {
  // Deflate compresses at most 1032 to 1: a claim beyond that cannot be
  // what the stream holds, and is refused before any memory is taken.
  if (expectedBytes / 1032 > compressed.size() + 64)
    return "the " + std::to_string(compressed.size()) + " compressed bytes cannot hold the " +
           std::to_string(expectedBytes) + " bytes expected";
  out.assign(expectedBytes, '\0');
  z_stream z{};
  // 15 + 32: a zlib or a gzip header, detected.
  if (inflateInit2(&z, 15 + 32) != Z_OK) return "cannot start zlib";
  std::size_t in = 0, produced = 0;
  int status = Z_OK;
  char overflow[64];
  int stalled = 0;
  while (status == Z_OK) {
    // zlib counts in 32-bit units: input and output go in pieces of 1 GiB.
    if (z.avail_in == 0 && in < compressed.size()) {
      const std::size_t piece = std::min<std::size_t>(compressed.size() - in, std::size_t{1} << 30);
      z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data() + in));
      z.avail_in = static_cast<uInt>(piece);
      in += piece;
    }
    const bool intoOverflow = produced >= expectedBytes;
    const std::size_t room = intoOverflow ? sizeof overflow
                                          : std::min<std::size_t>(expectedBytes - produced, std::size_t{1} << 30);
    z.next_out = reinterpret_cast<Bytef*>(intoOverflow ? overflow : out.data() + produced);
    z.avail_out = static_cast<uInt>(room);
    status = inflate(&z, Z_NO_FLUSH);
    const std::size_t made = room - z.avail_out;
    if (intoOverflow && made > 0) {
      inflateEnd(&z);
      out.clear();
      return "the data inflate to more than the " + std::to_string(expectedBytes) + " bytes expected";
    }
    produced += made;
    if (status == Z_BUF_ERROR && z.avail_in == 0 && in >= compressed.size()) break;
    if (status == Z_BUF_ERROR) {  // no progress with this input: the loop gives more
      if (++stalled > 2) break;
      status = Z_OK;
    } else {
      stalled = 0;
    }
  }
  inflateEnd(&z);
  if (status == Z_DATA_ERROR || status == Z_NEED_DICT || status == Z_STREAM_ERROR || status == Z_MEM_ERROR) {
    out.clear();
    return "not a valid zlib or gzip stream";
  }
  if (status != Z_STREAM_END || produced != expectedBytes) {
    out.clear();
    return "the compressed data end after " + std::to_string(produced) + " of the " +
           std::to_string(expectedBytes) + " bytes expected";
  }
  return "";
}

std::string inflatePrefix(const std::string& compressed, std::size_t maxBytes, std::string& out) {
  out.clear();
  if (maxBytes / 1032 > compressed.size() + 64) maxBytes = (compressed.size() + 64) * 1032;
  z_stream z{};
  if (inflateInit2(&z, 15 + 32) != Z_OK) return "cannot start zlib";
  std::size_t in = 0;
  int status = Z_OK, stalled = 0;
  char chunk[1 << 16];
  while (status == Z_OK && out.size() < maxBytes) {
    if (z.avail_in == 0 && in < compressed.size()) {
      const std::size_t piece = std::min<std::size_t>(compressed.size() - in, std::size_t{1} << 30);
      z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data() + in));
      z.avail_in = static_cast<uInt>(piece);
      in += piece;
    }
    const std::size_t room = std::min<std::size_t>(sizeof chunk, maxBytes - out.size());
    z.next_out = reinterpret_cast<Bytef*>(chunk);
    z.avail_out = static_cast<uInt>(room);
    status = inflate(&z, Z_NO_FLUSH);
    out.append(chunk, room - z.avail_out);
    if (status == Z_BUF_ERROR) {
      if (++stalled > 2 || (z.avail_in == 0 && in >= compressed.size())) break;
      status = Z_OK;
    } else {
      stalled = 0;
    }
  }
  inflateEnd(&z);
  if (status == Z_DATA_ERROR || status == Z_NEED_DICT || status == Z_STREAM_ERROR || status == Z_MEM_ERROR) {
    out.clear();
    return "not a valid zlib or gzip stream";
  }
  return "";
}

}  // namespace stvd::surface_io::detail
