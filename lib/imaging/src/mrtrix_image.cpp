// MRtrix image files: our own parser and writer (see mrtrix_image.hpp).
#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/imaging/detail/read_progress.hpp"

#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "stvd/errors.hpp"
#include "stvd/imaging/detail/image_header_screening.hpp"
#include "stvd/imaging/label_values.hpp"
#include "stvd/system/files/file_contents.hpp"
#include "stvd/system/files/output_transaction.hpp"
#include "stvd/system/files/regular_file.hpp"

namespace stvd::imaging {
namespace {

namespace fs = std::filesystem;

/// A header longer than this is not a header (MRtrix's own are a few kB,
/// long diffusion schemes included).
constexpr std::size_t kMaxHeaderBytes = 16u << 20;
/// At most this many axes (MRtrix's own limit is 16).
constexpr std::size_t kMaxAxes = 16;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() > suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string trim(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && std::isspace(static_cast<unsigned char>(s[b]))) ++b;
  while (e > b && std::isspace(static_cast<unsigned char>(s[e - 1]))) --e;
  return std::string(s.substr(b, e - b));
}

std::vector<std::string> split(const std::string& s, char separator) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(s);
  while (std::getline(in, part, separator)) parts.push_back(trim(part));
  if (!s.empty() && s.back() == separator) parts.emplace_back();
  return parts;
}

bool parseUnsigned(const std::string& text, unsigned long long limit, unsigned long long& value) {
  if (text.empty() || text.size() > 19 || !std::all_of(text.begin(), text.end(), [](char c) {
        return std::isdigit(static_cast<unsigned char>(c));
      }))
    return false;
  value = std::strtoull(text.c_str(), nullptr, 10);
  return value <= limit;
}

bool parseFinite(const std::string& text, double& value) {
  if (text.empty()) return false;
  errno = 0;
  char* end = nullptr;
  value = std::strtod(text.c_str(), &end);
  return *end == '\0' && errno != ERANGE && std::isfinite(value);
}

/// Bytes per element of an MRtrix datatype name (0 for Bit), and whether it
/// is stored big-endian, floating point and signed. False for an unknown name.
struct DataType {
  int bytes = 0;
  bool bigEndian = false, floating = false, isSigned = false;
};

bool parseDataType(const std::string& written, DataType& t) {
  std::string name = lower(written);
  if (name == "bit") return t = {0, false, false, false}, true;
  if (name == "int8") return t = {1, false, false, true}, true;
  if (name == "uint8") return t = {1, false, false, false}, true;
  bool big = false;
  if (endsWith(name, "le")) {
    name.resize(name.size() - 2);
  } else if (endsWith(name, "be")) {
    name.resize(name.size() - 2);
    big = true;
  }  // without a suffix: the machine's order, little-endian on every machine stvd builds for
  static const struct { const char* name; DataType type; } types[] = {
      {"int16", {2, false, false, true}},  {"uint16", {2, false, false, false}},
      {"int32", {4, false, false, true}},  {"uint32", {4, false, false, false}},
      {"int64", {8, false, false, true}},  {"uint64", {8, false, false, false}},
      {"float32", {4, false, true, true}}, {"float64", {8, false, true, true}},
  };
  for (const auto& entry : types)
    if (name == entry.name) {
      t = entry.type;
      t.bigEndian = big;
      return true;
    }
  return false;
}

bool hostIsLittleEndian() {
  const std::uint16_t one = 1;
  unsigned char first;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

/// One element at element position `at` of the data, as a double.
double element(const unsigned char* data, std::size_t at, const DataType& t, bool swap) {
  if (t.bytes == 0) return (data[at / 8] >> (7 - at % 8)) & 1;  // Bit: the first element in the top bit
  unsigned char b[8];
  std::memcpy(b, data + at * t.bytes, t.bytes);
  if (swap) std::reverse(b, b + t.bytes);
  switch (t.bytes) {
    case 1: return t.isSigned ? double(static_cast<std::int8_t>(b[0])) : double(b[0]);
    case 2: {
      std::uint16_t u;
      std::memcpy(&u, b, 2);
      return t.isSigned ? double(static_cast<std::int16_t>(u)) : double(u);
    }
    case 4: {
      if (t.floating) {
        float f;
        std::memcpy(&f, b, 4);
        return f;
      }
      std::uint32_t u;
      std::memcpy(&u, b, 4);
      return t.isSigned ? double(static_cast<std::int32_t>(u)) : double(u);
    }
    default: {
      if (t.floating) {
        double d;
        std::memcpy(&d, b, 8);
        return d;
      }
      std::uint64_t u;
      std::memcpy(&u, b, 8);
      return t.isSigned ? double(static_cast<std::int64_t>(u)) : double(u);
    }
  }
}

GridGeometry geometryOf(const MrtrixHeader& h, const std::string& name) {
  GridGeometry g;
  for (int a = 0; a < 3; ++a) {
    g.size[a] = a < static_cast<int>(h.size.size()) ? h.size[a] : 1;
    g.spacing[a] = h.spacing[a];
    // RAS -> LPS: negate x and y of every column and of the translation.
    for (int r = 0; r < 3; ++r) g.direction[3 * r + a] = (r < 2 ? -1.0 : 1.0) * h.transform[4 * r + a];
    g.origin[a] = (a < 2 ? -1.0 : 1.0) * h.transform[4 * a + 3];
  }
  try {
    g.validate();
  } catch (const std::invalid_argument& e) {
    throw ImageIoError(name, std::string("unusable image geometry: ") + e.what());
  }
  return g;
}

/// Calls visit(e, at) for every element in logical order (axis 0 fastest):
/// e counts elements, `at` is the element's position in the stored data.
/// The position moves by each axis's stride, back by a whole axis when it
/// wraps.
template <class Visit>
void forEachElement(const MrtrixHeader& header, Visit visit) {
  const std::size_t n = header.elementCount(), axes = header.size.size();
  std::vector<std::size_t> index(axes, 0);
  long long at = static_cast<long long>(header.firstElement);
  for (std::size_t e = 0; e < n; ++e) {
    visit(e, static_cast<std::size_t>(at));
    for (std::size_t a = 0; a < axes; ++a) {
      at += header.strides[a];
      if (++index[a] < header.size[a]) break;
      at -= header.strides[a] * static_cast<long long>(header.size[a]);
      index[a] = 0;
    }
  }
}

bool isScaled(const MrtrixHeader& h) { return !(h.scalingOffset == 0.0 && h.scalingMultiplier == 1.0); }

std::vector<float> decodeValues(const MrtrixHeader& header, std::string_view data, InterruptScope& progress,
                                std::uint64_t from) {
  DataType type;
  parseDataType(header.datatype, type);
  const bool swap = type.bytes > 1 && type.bigEndian == hostIsLittleEndian();
  const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
  std::vector<float> values(header.elementCount());
  // Without scaling a value is taken as stored (-0 stays -0, a NaN keeps
  // its bits), so that a written file reads back bit for bit.
  const bool scaled = isScaled(header);
  forEachElement(header, [&](std::size_t e, std::size_t at) {
    progress.step(from + e);
    const double raw = element(bytes, at, type, swap);
    values[e] = static_cast<float>(scaled ? header.scalingOffset + header.scalingMultiplier * raw : raw);
  });
  return values;
}

/// Labels: integer datatypes without scaling exactly (64-bit), every other
/// value through the rules for floating-point labels (stvd/imaging/label_values.hpp).
std::vector<std::int64_t> decodeLabels(const MrtrixHeader& header, std::string_view data, const GridGeometry& g,
                                       const std::string& name, InterruptScope& progress, std::uint64_t from) {
  DataType type;
  parseDataType(header.datatype, type);
  const bool swap = type.bytes > 1 && type.bigEndian == hostIsLittleEndian();
  const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
  std::vector<std::int64_t> labels(header.elementCount());
  const bool exact = !type.floating && !isScaled(header);
  forEachElement(header, [&](std::size_t e, std::size_t at) {
    progress.step(from + e);
    if (!exact) {
      const double raw = element(bytes, at, type, swap);
      labels[e] = labelOfReal(isScaled(header) ? header.scalingOffset + header.scalingMultiplier * raw : raw,
                                      name, g, e);
      return;
    }
    if (type.bytes == 0) {
      labels[e] = (bytes[at / 8] >> (7 - at % 8)) & 1;
      return;
    }
    // The stored bytes in the file's byte order, assembled exactly.
    const unsigned char* stored = bytes + at * type.bytes;
    std::uint64_t u = 0;
    for (int k = 0; k < type.bytes; ++k)
      u |= std::uint64_t{stored[type.bigEndian ? type.bytes - 1 - k : k]} << (8 * k);
    if (type.isSigned) {
      const int unused = 64 - 8 * type.bytes;  // sign-extend
      labels[e] = unused == 0 ? static_cast<std::int64_t>(u)
                              : static_cast<std::int64_t>(u << unused) >> unused;
    } else {
      labels[e] = labelOfUnsigned64(u, name, g, e);
    }
  });
  return labels;
}

/// The end of the header (the byte after "END" and its line break), or
/// npos when `bytes` holds no complete header.
std::size_t headerEnd(std::string_view bytes) {
  std::size_t from = 0;
  while (true) {
    const std::size_t at = bytes.find("\nEND", from);
    if (at == std::string_view::npos || at > kMaxHeaderBytes) return std::string_view::npos;
    std::size_t after = at + 4;
    if (after < bytes.size() && bytes[after] == '\r') ++after;
    if (after < bytes.size() && bytes[after] == '\n') return after + 1;
    if (after == bytes.size()) return after;
    from = at + 1;
  }
}

/// `size` bytes of the file at `path` from byte `offset` (fewer when the
/// file is shorter: never more than it holds, whatever a header says).
std::string readRange(const std::string& path, std::uint64_t offset, std::size_t size, const std::string& name) {
  std::optional<files::RegularFile> file;
  try {
    file.emplace(path);  // never blocks on a FIFO swapped in after the checks
  } catch (const files::InputFileError& e) {
    throw ImageIoError(name, path == name ? e.problem() : e.what());
  }
  std::string content(size, '\0');
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::pread(file->descriptor(), content.data() + done, size - done,
                              static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw ImageIoError(name, "cannot read " + path + ": " + std::strerror(errno));
    if (n == 0) break;
    done += static_cast<std::size_t>(n);
  }
  content.resize(done);
  return content;
}

/// Reads up to `size` decompressed bytes into `into` (nullptr: counts them
/// only); the count read. Throws ImageIoError for a damaged stream.
std::size_t gzipRead(gzFile file, const std::string& path, char* into, std::size_t size) {
  std::vector<char> scratch(into ? 0 : std::min<std::size_t>(size, 1u << 20));
  std::size_t done = 0;
  while (done < size) {
    const unsigned want = static_cast<unsigned>(std::min<std::size_t>(size - done, 1u << 20));
    const int got = gzread(file, into ? into + done : scratch.data(), want);
    int error = Z_OK;
    if (got <= 0) gzerror(file, &error);
    if (got < 0 || (error != Z_OK && error != Z_STREAM_END))
      throw ImageIoError(path, "the compressed data are damaged or cut short");
    if (got == 0) break;
    done += static_cast<std::size_t>(got);
  }
  return done;
}

/// The checked header of the file at `path` and its data bytes (the data
/// alone, without the header).
struct StoredImage {
  MrtrixHeader header;
  std::string data;
};

/// The first bytes of a .mif.gz stream, up to and including its header's
/// END line (or kMaxHeaderBytes and a little more when there is none).
std::string compressedHead(gzFile file, const std::string& path) {
  std::string head;
  std::vector<char> chunk(4096);
  while (headerEnd(head) == std::string::npos && head.size() <= kMaxHeaderBytes) {
    const std::size_t got = gzipRead(file, path, chunk.data(), chunk.size());
    if (got == 0) break;
    head.append(chunk.data(), got);
  }
  return head;
}

struct GzCloser {
  void operator()(gzFile_s* f) const { gzclose(f); }
};

/// `path` opened through zlib, once it is known to be a regular file (a
/// device or FIFO could be read from forever), without blocking on a FIFO
/// swapped in meanwhile.
std::unique_ptr<gzFile_s, GzCloser> openCompressed(const std::string& path) {
  int fd;
  try {
    fd = files::RegularFile(path).release();
  } catch (const files::InputFileError& e) {
    throw ImageIoError(path, e.problem());
  }
  std::unique_ptr<gzFile_s, GzCloser> file(gzdopen(fd, "rb"));
  if (!file) {
    ::close(fd);
    throw ImageIoError(path, "cannot open the compressed file");
  }
  return file;
}

/// A .mif.gz file decompressed as far as its header says, never further.
/// A header that declares more than deflate can expand the file to (1032
/// to 1), or more than the memory available, fails at once. Otherwise the
/// stream is decompressed twice: once to find the header and to count how
/// far the data go (nothing stored), then into memory, so that a header
/// that declares more data than the stream holds fails before the data are
/// allocated.
StoredImage readCompressedMif(const std::string& path) {
  const auto open = [&path] { return openCompressed(path); };
  // A device or FIFO could be read from forever; deflate's ratio bounds
  // what a regular file of this size can hold.
  const std::uint64_t compressedBytes = detail::regularFileSize(path, path, "the file");
  auto first = open();
  const std::string head = compressedHead(first.get(), path);
  StoredImage stored;
  stored.header = parseMrtrixHeader(head, path);  // names what is missing when there is no END
  const MrtrixHeader& header = stored.header;
  if (header.dataFile != ".") throw ImageIoError(path, "a .mif.gz file must hold its own data (file: . OFFSET)");
  const std::size_t needed = header.dataOffset + header.dataBytes();
  if (static_cast<double>(needed) > detail::kMaxDeflateRatio * static_cast<double>(compressedBytes) + 65536.0)
    throw ImageIoError(path, "the header declares " + std::to_string(needed) + " bytes, more than the " +
                                 std::to_string(compressedBytes) + " compressed bytes can hold");
  detail::checkValuesFitInMemory(header.elementCount(), header.bytesPerElement, path);
  const std::size_t available =
      head.size() >= needed ? needed : head.size() + gzipRead(first.get(), path, nullptr, needed - head.size());
  if (available < needed)
    throw ImageIoError(path, "the file is truncated: " + std::to_string(available) +
                                 " decompressed bytes where header and data need " + std::to_string(needed));
  auto second = open();
  std::string content(needed, '\0');
  if (gzipRead(second.get(), path, content.data(), needed) != needed)
    throw ImageIoError(path, "the compressed data changed while being read");
  content.erase(0, header.dataOffset);
  stored.data = std::move(content);
  return stored;
}

/// `bytes` as one gzip stream (zlib level 6, as gzip's default). The
/// header zlib writes has no time stamp and no file name, so the same bytes
/// always give the same stream.
std::string gzipCompressed(const std::string& bytes, const std::string& name) {
  z_stream z{};
  if (deflateInit2(&z, 6, Z_DEFLATED, 15 + 16, 8, Z_DEFAULT_STRATEGY) != Z_OK)
    throw ImageIoError(name, "cannot start the gzip compression");
  std::string out;
  out.reserve(deflateBound(&z, bytes.size()));
  std::vector<char> chunk(1 << 20);
  std::size_t fed = 0;
  int status = Z_OK;
  do {
    // zlib counts in 32-bit units: the input goes in pieces of 1 GiB.
    if (z.avail_in == 0 && fed < bytes.size()) {
      z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data() + fed));
      z.avail_in = static_cast<uInt>(std::min<std::size_t>(bytes.size() - fed, 1u << 30));
      fed += z.avail_in;
    }
    z.next_out = reinterpret_cast<Bytef*>(chunk.data());
    z.avail_out = static_cast<uInt>(chunk.size());
    status = deflate(&z, fed == bytes.size() ? Z_FINISH : Z_NO_FLUSH);
    out.append(chunk.data(), chunk.size() - z.avail_out);
  } while (status == Z_OK || status == Z_BUF_ERROR);
  deflateEnd(&z);
  if (status != Z_STREAM_END) throw ImageIoError(name, "the gzip compression failed");
  return out;
}

}  // namespace

std::size_t MrtrixHeader::elementCount() const {
  std::size_t n = 1;
  for (std::size_t s : size) n *= s;
  return n;
}

std::size_t MrtrixHeader::dataBytes() const {
  const std::size_t n = elementCount();
  return bytesPerElement == 0 ? (n + 7) / 8 : n * static_cast<std::size_t>(bytesPerElement);
}

bool isMrtrixImagePath(const std::string& path) {
  const std::string l = lower(path);
  const std::string name = fs::path(l).filename().string();
  for (const char* ext : {".mif", ".mif.gz", ".mih"})
    if (endsWith(name, ext)) return true;
  return false;
}

MrtrixHeader parseMrtrixHeader(std::string_view bytes, const std::string& name, bool endsWithText) {
  const std::string_view magic = "mrtrix image";
  if (bytes.substr(0, magic.size()) != magic ||
      (bytes.size() > magic.size() && bytes[magic.size()] != '\n' && bytes[magic.size()] != '\r'))
    throw ImageIoError(name, "not an MRtrix image (it does not start with \"mrtrix image\")");
  std::size_t end = headerEnd(bytes);
  if (end == std::string_view::npos && endsWithText && bytes.size() <= kMaxHeaderBytes) end = bytes.size();
  if (end == std::string_view::npos)
    throw ImageIoError(name, "the MRtrix header has no END line" +
                                 std::string(bytes.size() > kMaxHeaderBytes ? " in its first 16 MiB" : ""));
  MrtrixHeader h;
  std::string dim, vox, layout, datatype, scaling;
  std::vector<std::string> transform, files;
  std::size_t lineNumber = 1;
  std::size_t at = bytes.find('\n') + 1;
  while (at < end) {
    std::size_t next = bytes.find('\n', at);
    if (next == std::string_view::npos || next > end) next = end;
    const std::string line = trim(bytes.substr(at, next - at));
    at = next + 1;
    ++lineNumber;
    if (line.empty()) continue;
    if (line == "END") break;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos)
      throw ImageIoError(name, "header line " + std::to_string(lineNumber) + " is not \"key: value\"");
    const std::string key = lower(trim(line.substr(0, colon))), value = trim(line.substr(colon + 1));
    if (key == "dim") dim = value;
    else if (key == "vox") vox = value;
    else if (key == "layout") layout = value;
    else if (key == "datatype") datatype = value;
    else if (key == "scaling") scaling = value;
    else if (key == "transform") transform.push_back(value);
    else if (key == "file") files.push_back(value);
  }
  for (const auto& [key, value] : {std::pair<const char*, const std::string*>{"dim", &dim}, {"vox", &vox},
                                   {"layout", &layout}, {"datatype", &datatype}})
    if (value->empty()) throw ImageIoError(name, std::string("the MRtrix header has no ") + key + " entry");
  if (files.empty()) throw ImageIoError(name, "the MRtrix header has no file entry");
  if (files.size() > 1)
    throw ImageIoError(name, "the image is split over " + std::to_string(files.size()) +
                                 " data files, which stvd does not read (mrconvert makes one .mif of it)");

  // dim: the sizes, and their product without overflow.
  const std::vector<std::string> sizes = split(dim, ',');
  if (sizes.size() > kMaxAxes) throw ImageIoError(name, "dim has " + std::to_string(sizes.size()) + " axes");
  unsigned long long product = 1;
  for (const std::string& s : sizes) {
    unsigned long long n;
    if (!parseUnsigned(s, std::numeric_limits<std::uint32_t>::max(), n) || n == 0)
      throw ImageIoError(name, "dim: '" + dim + "' is not a list of positive sizes");
    if (__builtin_mul_overflow(product, n, &product) || product > (1ull << 40))
      throw ImageIoError(name, "dim: " + dim + " declares an absurd number of values");
    h.size.push_back(static_cast<std::size_t>(n));
  }

  // vox: the first three spacings must be positive numbers.
  const std::vector<std::string> spacings = split(vox, ',');
  for (std::size_t a = 0; a < std::min<std::size_t>(3, h.size.size()); ++a) {
    double s;
    if (a >= spacings.size() || !parseFinite(spacings[a], s) || !(s > 0.0))
      throw ImageIoError(name, "vox: '" + vox + "' does not give a positive voxel size for axis " + std::to_string(a));
    detail::checkCoordinate(s, "the voxel size of axis " + std::to_string(a), name);
    h.spacing[a] = s;
  }

  // layout: a sign and a rank per axis, the ranks a permutation.
  const std::vector<std::string> entries = split(layout, ',');
  if (entries.size() != h.size.size())
    throw ImageIoError(name, "layout: '" + layout + "' does not have one entry per axis of dim " + dim);
  std::vector<int> rankOf(h.size.size());
  std::vector<int> axisOfRank(h.size.size(), -1);
  std::vector<bool> reversed(h.size.size());
  for (std::size_t a = 0; a < entries.size(); ++a) {
    const std::string& e = entries[a];
    unsigned long long rank;
    if (e.size() < 2 || (e[0] != '+' && e[0] != '-') || !parseUnsigned(e.substr(1), h.size.size() - 1, rank) ||
        axisOfRank[rank] >= 0)
      throw ImageIoError(name, "layout: '" + layout + "' is not a signed order of the axes (such as -0,+1,+2)");
    rankOf[a] = static_cast<int>(rank);
    axisOfRank[rank] = static_cast<int>(a);
    reversed[a] = e[0] == '-';
  }
  h.strides.assign(h.size.size(), 0);
  long long stride = 1;
  for (std::size_t r = 0; r < axisOfRank.size(); ++r) {
    const int a = axisOfRank[r];
    h.strides[a] = reversed[a] ? -stride : stride;
    if (reversed[a]) h.firstElement += static_cast<std::size_t>(stride) * (h.size[a] - 1);
    stride *= static_cast<long long>(h.size[a]);  // bounded by product above
  }

  DataType type;
  if (!parseDataType(datatype, type))
    throw ImageIoError(name, "datatype " + datatype +
                                 " is not one stvd reads (Bit, Int8, UInt8, [U]Int16/32/64, Float32, Float64; "
                                 "LE or BE)");
  h.datatype = datatype;
  h.bytesPerElement = type.bytes;

  if (!scaling.empty()) {
    const std::vector<std::string> parts = split(scaling, ',');
    if (parts.size() != 2 || !parseFinite(parts[0], h.scalingOffset) || !parseFinite(parts[1], h.scalingMultiplier))
      throw ImageIoError(name, "scaling: '" + scaling + "' is not \"offset,multiplier\"");
  }

  if (!transform.empty()) {
    if (transform.size() != 3)
      throw ImageIoError(name, "the MRtrix header has " + std::to_string(transform.size()) +
                                   " transform lines, not 3");
    for (int r = 0; r < 3; ++r) {
      const std::vector<std::string> row = split(transform[r], ',');
      if (row.size() != 4)
        throw ImageIoError(name, "transform line " + std::to_string(r + 1) + " is not four numbers");
      for (int c = 0; c < 4; ++c) {
        if (!parseFinite(row[c], h.transform[4 * r + c]))
          throw ImageIoError(name, "transform line " + std::to_string(r + 1) + " is not four finite numbers");
        detail::checkCoordinate(h.transform[4 * r + c],
                                "transform entry (" + std::to_string(r + 1) + ", " + std::to_string(c + 1) + ")", name);
      }
    }
  }

  // file: NAME [OFFSET]
  std::istringstream file(files.front());
  std::string offset, rest;
  file >> h.dataFile >> offset >> rest;
  unsigned long long byteOffset = 0;
  if (h.dataFile.empty() || !rest.empty() ||
      (!offset.empty() && !parseUnsigned(offset, std::numeric_limits<long long>::max(), byteOffset)))
    throw ImageIoError(name, "file: '" + files.front() + "' is not \"NAME [OFFSET]\"");
  if (h.dataFile == "." && byteOffset < end)
    throw ImageIoError(name, "file: the data offset " + offset + " lies inside the header");
  h.dataOffset = static_cast<std::size_t>(byteOffset);
  const std::size_t dataBytes = h.dataBytes();
  if (h.dataOffset > std::numeric_limits<std::size_t>::max() - dataBytes)
    throw ImageIoError(name, "file: the data offset " + offset + " is absurd");
  geometryOf(h, name);  // an unusable grid fails here, before any data are read
  return h;
}

MrtrixImage parseMrtrixImage(std::string_view bytes, const std::string& name) {
  const MrtrixHeader header = parseMrtrixHeader(bytes, name);
  if (header.dataFile != ".")
    throw ImageIoError(name, "the data are in another file (" + header.dataFile + "), not after the header");
  const std::size_t needed = header.dataOffset + header.dataBytes();
  if (bytes.size() < needed)
    throw ImageIoError(name, "the file is truncated: " + std::to_string(bytes.size()) +
                                 " bytes where header and data need " + std::to_string(needed));
  MrtrixImage image;
  image.geometry = geometryOf(header, name);
  InterruptScope none(nullptr, "", 0);
  image.values = decodeValues(header, bytes.substr(header.dataOffset, header.dataBytes()), none, 0);
  image.header = header;
  return image;
}

namespace {

/// The header of a .mif or .mih file of `fileBytes` bytes, from its first
/// bytes (a .mih header ends with its text, MRtrix writes no END there).
MrtrixHeader readUncompressedHeader(const std::string& path, std::uint64_t fileBytes) {
  const std::string head =
      readRange(path, 0, static_cast<std::size_t>(std::min<std::uint64_t>(fileBytes, kMaxHeaderBytes + 8)), path);
  return parseMrtrixHeader(head, path, /*endsWithText=*/endsWith(lower(path), ".mih"));
}

/// The file that holds the data: the header's own, or the one it names,
/// relative to the header's folder.
std::string dataFilePath(const std::string& path, const MrtrixHeader& header) {
  if (header.dataFile == ".") return path;
  const fs::path named(header.dataFile);
  return named.is_absolute() ? named.string() : (fs::path(path).parent_path() / named).string();
}

StoredImage readStoredImage(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw ImageIoError(path, "no such file");
  const std::string l = lower(path);
  if (endsWith(l, ".mif.gz")) return readCompressedMif(path);
  // .mif (header and data in one file) or .mih (the header alone, its data
  // in the file it names, next to it): the header first, then exactly the
  // data it declares, once they are known to be in the file and to fit in
  // memory.
  const bool mih = endsWith(l, ".mih");
  StoredImage stored;
  const std::uint64_t fileBytes = detail::regularFileSize(path, path, "the file");
  stored.header = readUncompressedHeader(path, fileBytes);
  const MrtrixHeader& h = stored.header;
  if (!mih && h.dataFile != ".")
    throw ImageIoError(path, "the data are in another file (" + h.dataFile + "), not after the header");
  const std::string dataPath = dataFilePath(path, h);
  const std::uint64_t dataFileBytes =
      h.dataFile == "." ? fileBytes : detail::regularFileSize(dataPath, path, "its data file");
  const std::uint64_t needed = static_cast<std::uint64_t>(h.dataOffset) + h.dataBytes();
  if (dataFileBytes < needed)
    throw ImageIoError(path, (h.dataFile == "." ? std::string("the file") : "its data file " + dataPath) +
                                 " is truncated: " + std::to_string(dataFileBytes) + " bytes where " +
                                 (h.dataFile == "." ? "header and data need " : "the data need ") +
                                 std::to_string(needed));
  detail::checkValuesFitInMemory(h.elementCount(), h.bytesPerElement, path);
  stored.data = readRange(dataPath, h.dataOffset, h.dataBytes(), path);
  if (stored.data.size() != h.dataBytes()) throw ImageIoError(path, "cannot read the data of " + dataPath);
  return stored;
}

}  // namespace

MrtrixImage readMrtrixImage(const std::string& path, Interrupter* interrupter) {
  InterruptScope progress(interrupter, "reading image", 0);
  MrtrixImage image = detail::readMrtrixImage(path, progress);
  progress.finish();
  return image;
}

MrtrixLabelImage readMrtrixLabelImage(const std::string& path, Interrupter* interrupter) {
  InterruptScope progress(interrupter, "reading labels", 0);
  MrtrixLabelImage image = detail::readMrtrixLabelImage(path, progress);
  progress.finish();
  return image;
}

namespace detail {

MrtrixImage readMrtrixImage(const std::string& path, InterruptScope& progress, std::uint64_t stepsAfter) {
  StoredImage stored = readStoredImage(path);  // the bytes: read (and inflated) in one piece
  const std::uint64_t values = stored.header.elementCount();
  progress.setTotal(2 * values + stepsAfter);
  progress.check(values);
  MrtrixImage image;
  image.geometry = geometryOf(stored.header, path);
  image.values = decodeValues(stored.header, stored.data, progress, values);
  image.header = std::move(stored.header);
  return image;
}

MrtrixLabelImage readMrtrixLabelImage(const std::string& path, InterruptScope& progress) {
  StoredImage stored = readStoredImage(path);
  const std::uint64_t values = stored.header.elementCount();
  progress.setTotal(2 * values);
  progress.check(values);
  MrtrixLabelImage image;
  image.geometry = geometryOf(stored.header, path);
  image.labels = decodeLabels(stored.header, stored.data, image.geometry, path, progress, values);
  image.header = std::move(stored.header);
  return image;
}

}  // namespace detail

GridGeometry readMrtrixImageGrid(const std::string& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw ImageIoError(path, "no such file");
  if (endsWith(lower(path), ".mif.gz")) {
    const auto file = openCompressed(path);
    return geometryOf(parseMrtrixHeader(compressedHead(file.get(), path), path), path);
  }
  return geometryOf(readUncompressedHeader(path, detail::regularFileSize(path, path, "the file")), path);
}

std::string mrtrixDataFile(const std::string& path) {
  if (!endsWith(lower(path), ".mih")) return path;
  try {
    return dataFilePath(path, readUncompressedHeader(path, detail::regularFileSize(path, path, "the file")));
  } catch (const ImageIoError&) {
    return "";
  }
}

MrtrixAxisOrder mrtrixAxisOrder(const GridGeometry& g) {
  // The image axes in RAS: columns of the direction matrix with x and y negated.
  double ras[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) ras[r][c] = (r < 2 ? -1.0 : 1.0) * g.direction[3 * r + c];
  // For each scanner axis (row), the image axis closest to it; ties and
  // repeats resolved to a permutation the way MRtrix does.
  MrtrixAxisOrder order;
  for (int r = 0; r < 3; ++r) {
    int best = 0;
    for (int c = 1; c < 3; ++c)
      if (std::abs(ras[r][c]) > std::abs(ras[r][best])) best = c;
    order.axis[r] = best;
  }
  const auto other = [](int a, int b) {
    for (int i = 0; i < 3; ++i)
      if (i != a && i != b) return i;
    return 0;
  };
  auto& p = order.axis;
  if (p[0] == p[1]) p[1] = other(p[0], p[2]);
  if (p[0] == p[2]) p[2] = other(p[0], p[1]);
  if (p[1] == p[2]) p[2] = other(p[0], p[1]);
  for (int r = 0; r < 3; ++r) order.reversed[r] = ras[r][p[r]] < 0.0;
  return order;
}

std::array<long, 3> mrtrixVoxelIndex(const GridGeometry& g, const std::array<long, 3>& index) {
  const MrtrixAxisOrder order = mrtrixAxisOrder(g);
  std::array<long, 3> shown{};
  for (int r = 0; r < 3; ++r) {
    const int a = order.axis[r];
    shown[r] = order.reversed[r] ? static_cast<long>(g.size[a]) - 1 - index[a] : index[a];
  }
  return shown;
}

void writeMrtrixImage(const std::string& path, const std::string& formatPath, const GridGeometry& g,
                      const std::vector<float>& values, std::size_t volumes) {
  if (volumes == 0 || values.size() != g.voxelCount() * volumes)
    throw ImageIoError(formatPath, std::to_string(values.size()) + " values for " + std::to_string(volumes) +
                                       " volume(s) of " + std::to_string(g.voxelCount()) + " voxels");
  const std::string l = lower(formatPath);
  const bool gzip = endsWith(l, ".mif.gz");
  if (!gzip && !endsWith(l, ".mif"))
    throw ImageIoError(formatPath, "MRtrix images are written as .mif or .mif.gz");
  std::ostringstream head;
  head.precision(17);
  head << "mrtrix image\ndim: " << g.size[0] << "," << g.size[1] << "," << g.size[2];
  if (volumes > 1) head << "," << volumes;
  head << "\nvox: " << g.spacing[0] << "," << g.spacing[1] << "," << g.spacing[2] << (volumes > 1 ? ",1" : "");
  head << "\nlayout: +0,+1,+2" << (volumes > 1 ? ",+3" : "") << "\ndatatype: Float32LE\n";
  for (int r = 0; r < 3; ++r) {
    const double flip = r < 2 ? -1.0 : 1.0;  // LPS -> RAS
    head << "transform: " << flip * g.direction[3 * r] << "," << flip * g.direction[3 * r + 1] << ","
         << flip * g.direction[3 * r + 2] << "," << flip * g.origin[r] << "\n";
  }
  // The data start on a 16-byte boundary after "file: . OFFSET\nEND\n";
  // the offset's own digits count, hence the loop.
  const std::string start = head.str();
  std::size_t offset = 0;
  do {
    const std::size_t length = start.size() + std::string("file: . \nEND\n").size() + std::to_string(offset).size();
    const std::size_t aligned = (length + 15) / 16 * 16;
    if (aligned == offset) break;
    offset = aligned;
  } while (true);
  std::string content = start + "file: . " + std::to_string(offset) + "\nEND\n";
  content.resize(offset + values.size() * 4, '\0');
  for (std::size_t i = 0; i < values.size(); ++i) {
    unsigned char b[4];
    std::memcpy(b, &values[i], 4);
    if (!hostIsLittleEndian()) std::reverse(b, b + 4);
    std::memcpy(&content[offset + 4 * i], b, 4);
  }
  try {
    files::writeFileContents(path, gzip ? gzipCompressed(content, formatPath) : content);
  } catch (const files::OutputError& e) {
    std::string problem = e.what();
    problem.erase(0, e.path().size() + 2);
    throw ImageIoError(formatPath, problem);
  }
}

Matrix3 mrtrixStoredVoxelAxes(const MrtrixHeader& header, const GridGeometry& geometryLps) {
  std::array<int, 3> byStride{0, 1, 2};
  std::sort(byStride.begin(), byStride.end(), [&](int a, int b) {
    return std::llabs(header.strides[a]) < std::llabs(header.strides[b]);
  });
  const Matrix3 logical = voxelAxes(geometryLps);
  Matrix3 stored{};
  for (int s = 0; s < 3; ++s) {
    const int a = byStride[s];
    const double sign = header.strides[a] < 0 ? -1.0 : 1.0;
    for (int r = 0; r < 3; ++r) stored[3 * r + s] = sign * logical[3 * r + a];
  }
  return stored;
}

}  // namespace stvd::imaging
