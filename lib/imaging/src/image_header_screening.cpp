#include "stvd/imaging/detail/image_header_screening.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <set>
#include <sstream>

#include "stvd/errors.hpp"
#include "stvd/system/files/regular_file.hpp"
#include "stvd/system/memory.hpp"

namespace stvd::imaging::detail {
namespace {

std::string lowercase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string number(double x) {
  std::ostringstream s;
  s.precision(6);
  s << x;
  return s.str();
}

std::string gigabytes(double bytes) {
  std::ostringstream s;
  s.precision(3);
  s << bytes / 1e9 << " GB";
  return s.str();
}

/// a * b, or false when it overflows 64 bits.
bool multiply(std::uint64_t a, std::uint64_t b, std::uint64_t& product) {
  return !__builtin_mul_overflow(a, b, &product);
}

// --- gzip streams -----------------------------------------------------------

struct GzCloser {
  void operator()(gzFile_s* f) const { gzclose(f); }
};
using GzFile = std::unique_ptr<gzFile_s, GzCloser>;

/// Opens `path` at byte `offset` for reading through zlib (gzip data are
/// decompressed, other data passed through as they are).
GzFile openAt(const std::string& path, std::uint64_t offset, const std::string& reportedPath) {
  int fd;
  try {
    fd = files::RegularFile(path).release();  // a FIFO swapped in after the checks does not block
  } catch (const files::InputFileError& e) {
    throw ImageIoError(reportedPath, "cannot open " + path + ": " + e.problem());
  }
  if (::lseek(fd, static_cast<off_t>(offset), SEEK_SET) < 0) {
    ::close(fd);
    throw ImageIoError(reportedPath, "cannot seek in " + path);
  }
  gzFile f = gzdopen(fd, "rb");
  if (!f) {
    ::close(fd);
    throw ImageIoError(reportedPath, "cannot open " + path);
  }
  gzbuffer(f, 1 << 16);
  return GzFile(f);
}

/// Decompressed bytes of the gzip stream that starts at `offset`, or -1
/// when it is damaged or cut short. Stops counting at `enough` (at most one
/// buffer beyond it).
long long gzipContentSize(const std::string& path, std::uint64_t offset, std::uint64_t enough,
                          const std::string& reportedPath) {
  const GzFile f = openAt(path, offset, reportedPath);
  std::vector<char> buffer(1 << 18);
  std::uint64_t total = 0;
  int n;
  while (total < enough && (n = gzread(f.get(), buffer.data(), static_cast<unsigned>(buffer.size()))) > 0)
    total += static_cast<std::uint64_t>(n);
  int error = Z_OK;
  gzerror(f.get(), &error);
  if (error != Z_OK && error != Z_STREAM_END && error != Z_BUF_ERROR) return -1;
  if (total < enough && error == Z_BUF_ERROR) return -1;  // the stream ends in the middle
  return static_cast<long long>(total);
}

void checkGzipHolds(const std::string& dataPath, std::uint64_t offset, std::uint64_t compressedBytes,
                    std::uint64_t needed, const std::string& reportedPath) {
  if (static_cast<double>(needed) > kMaxDeflateRatio * static_cast<double>(compressedBytes) + 65536.0)
    throw ImageIoError(reportedPath, "the header declares " + std::to_string(needed) +
                                         " bytes of data, more than the " + std::to_string(compressedBytes) +
                                         " compressed bytes can hold");
  // Counted only as far as the header needs: whatever follows (more gzip
  // members, zeros to the end of a disk) is never decompressed.
  const long long size = gzipContentSize(dataPath, offset, needed, reportedPath);
  if (size < 0) throw ImageIoError(reportedPath, "the compressed data are damaged or cut short");
  if (static_cast<std::uint64_t>(size) < needed)
    throw ImageIoError(reportedPath, "the file is truncated: its compressed data hold " + std::to_string(size) +
                                         " bytes where the header needs " + std::to_string(needed));
}

}  // namespace

/// Size of a regular file, after following symlinks. Throws for anything
/// else: a device or a FIFO can be read from forever.
std::uint64_t regularFileSize(const std::string& path, const std::string& reportedPath,
                              const std::string& role) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw ImageIoError(reportedPath, role + " " + path + ": " + std::strerror(errno));
  if (!S_ISREG(st.st_mode)) throw ImageIoError(reportedPath, role + " " + path + " is not a regular file");
  return static_cast<std::uint64_t>(st.st_size);
}

void checkValuesFitInMemory(std::uint64_t elements, unsigned elementBytes, const std::string& reportedPath) {
  // The reader holds the stored values and their single-precision copy.
  const double needed = static_cast<double>(elements) * (elementBytes + 4.0);
  // The same limit (system, control group, ulimit -v) the run's own memory
  // check uses later.
  const std::optional<AvailableMemory> memory = availableMemory();
  const std::uint64_t available = memory ? memory->bytes : 0;
  if (memory && needed > static_cast<double>(available))
    throw ImageIoError(reportedPath, "the header declares " + std::to_string(elements) +
                                         " values, which need " + gigabytes(needed) + " of memory; " +
                                         gigabytes(static_cast<double>(available)) + " are available");
}

void checkCoordinate(double x, const std::string& what, const std::string& reportedPath) {
  if (!std::isfinite(x))
    throw ImageIoError(reportedPath, what + " is not a finite number (" + number(x) + ")");
  if (std::abs(x) > kMaxCoordinateMm)
    throw ImageIoError(reportedPath, what + " is " + number(x) + ", beyond the " + number(kMaxCoordinateMm) +
                                         " mm that stvd accepts");
}

namespace {

// --- NIfTI ------------------------------------------------------------------

/// Bytes of one stored value of a NIfTI datatype, 0 when unknown.
unsigned niftiDatatypeBytes(std::int64_t datatype) {
  switch (datatype) {
    case 2: case 256: return 1;                 // uint8, int8
    case 4: case 512: return 2;                 // int16, uint16
    case 8: case 16: case 768: return 4;        // int32, float32, uint32
    case 64: case 1024: case 1280: return 8;    // float64, int64, uint64
    case 32: return 8;                          // complex64
    case 128: return 3;                         // rgb24
    case 2304: return 4;                        // rgba32
    case 1536: case 1792: return 16;            // float128, complex128
    case 2048: return 32;                       // complex256
    default: return 0;
  }
}

class HeaderBytes {
 public:
  HeaderBytes(const std::vector<unsigned char>& bytes, bool swapped) : b_(bytes), swapped_(swapped) {}
  template <class T>
  T get(std::size_t offset) const {
    unsigned char raw[sizeof(T)];
    std::memcpy(raw, b_.data() + offset, sizeof(T));
    if (swapped_) std::reverse(raw, raw + sizeof(T));
    T value;
    std::memcpy(&value, raw, sizeof(T));
    return value;
  }

 private:
  const std::vector<unsigned char>& b_;
  bool swapped_;
};

template <class T>
void put(std::vector<unsigned char>& bytes, std::size_t offset, T value, bool swapped) {
  unsigned char raw[sizeof(T)];
  std::memcpy(raw, &value, sizeof(T));
  if (swapped) std::reverse(raw, raw + sizeof(T));
  std::memcpy(bytes.data() + offset, raw, sizeof(T));
}

std::int32_t swapped32(std::int32_t v) { return static_cast<std::int32_t>(__builtin_bswap32(static_cast<std::uint32_t>(v))); }

/// Field offsets of the two header versions.
struct NiftiFields {
  std::size_t headerSize, datatype, dim, pixdim, voxOffset, sclSlope, sclInter, qformCode, sformCode, quatern,
      srow, intentCode;
  bool wide;  // NIfTI-2: int64 dims, double floats, int32 codes
};
constexpr NiftiFields kNifti1{348, 70, 40, 76, 108, 112, 116, 252, 254, 256, 280, 68, false};
constexpr NiftiFields kNifti2{540, 12, 16, 104, 168, 176, 184, 344, 348, 352, 400, 504, true};

ScreenedImage screenNifti(const std::string& path, const std::string& lower, bool withData) {
  ScreenedImage image;
  image.format = ImageFileFormat::Nifti;
  const bool pair = endsWith(lower, ".hdr") || endsWith(lower, ".hdr.gz") || endsWith(lower, ".img") ||
                    endsWith(lower, ".img.gz");
  std::string headerPath = path;
  if (pair) {  // the header is the .hdr, the data the .img, each possibly gzip-compressed
    const std::size_t stem = path.size() - (endsWith(lower, ".gz") ? 7 : 4);
    const std::string base = path.substr(0, stem);
    const bool upper = std::isupper(static_cast<unsigned char>(path[stem + 1])) != 0;
    auto firstExisting = [&](const char* plain, const char* compressed) {
      for (std::string ext : {plain, compressed}) {
        if (upper)
          for (char& c : ext) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
        if (::access((base + ext).c_str(), F_OK) == 0) return base + ext;
      }
      return std::string();
    };
    headerPath = firstExisting(".hdr", ".hdr.gz");
    image.dataPath = firstExisting(".img", ".img.gz");
    if (headerPath.empty()) throw ImageIoError(path, "the header file " + base + ".hdr of the pair is missing");
    if (image.dataPath.empty()) throw ImageIoError(path, "the image file " + base + ".img of the pair is missing");
  } else {
    image.dataPath = path;
  }
  regularFileSize(headerPath, path, "the header file");

  // The first 540 bytes, through zlib (which passes plain files through).
  std::vector<unsigned char> bytes(540, 0);
  int got;
  {
    const GzFile f = openAt(headerPath, 0, path);
    got = gzread(f.get(), bytes.data(), 540);
    int error = Z_OK;
    gzerror(f.get(), &error);
    if (got < 0 || (error != Z_OK && error != Z_STREAM_END && error != Z_BUF_ERROR))
      throw ImageIoError(path, "the compressed header is damaged");
  }
  std::int32_t sizeofHdr;
  std::memcpy(&sizeofHdr, bytes.data(), 4);
  const NiftiFields* fields = nullptr;
  if (sizeofHdr == 348 || swapped32(sizeofHdr) == 348) fields = &kNifti1;
  if (sizeofHdr == 540 || swapped32(sizeofHdr) == 540) fields = &kNifti2;
  if (!fields)
    throw ImageIoError(path, "not a NIfTI or Analyze header (its first field is " + std::to_string(sizeofHdr) +
                                 ", not 348 or 540)");
  if (got < static_cast<int>(fields->headerSize))
    throw ImageIoError(path, "the header is cut short (" + std::to_string(got) + " of " +
                                 std::to_string(fields->headerSize) + " bytes)");
  image.niftiSwapped = sizeofHdr != static_cast<std::int32_t>(fields->headerSize);
  bytes.resize(fields->headerSize);
  image.niftiHeader = bytes;
  const HeaderBytes h(image.niftiHeader, image.niftiSwapped);
  auto real = [&](std::size_t offset) {
    return fields->wide ? h.get<double>(offset) : static_cast<double>(h.get<float>(offset));
  };
  auto code = [&](std::size_t offset) {
    return fields->wide ? static_cast<std::int64_t>(h.get<std::int32_t>(offset))
                        : static_cast<std::int64_t>(h.get<std::int16_t>(offset));
  };

  if (fields->wide) {
    if (std::memcmp(bytes.data() + 4, "n+2\0\r\n\032\n", 8) != 0 && std::memcmp(bytes.data() + 4, "ni2\0\r\n\032\n", 8) != 0)
      throw ImageIoError(path, "a NIfTI-2 header without the NIfTI-2 magic");
    image.niftiVersion = 2;
  } else {
    // niftilib takes any "n+D" or "niD" (D a digit) as NIfTI magic.
    const char* magic = reinterpret_cast<const char*>(bytes.data() + 344);
    const bool nifti = magic[0] == 'n' && (magic[1] == '+' || magic[1] == 'i') && magic[2] >= '1' &&
                       magic[2] <= '9' && magic[3] == '\0';
    image.niftiVersion = nifti ? 1 : 0;
    if (image.niftiVersion == 0)
      image.warnings.push_back("has an Analyze 7.5 header (no NIfTI magic): the format does not define its "
                               "orientation, and the image is read with ITK's default orientation");
  }

  // Dimensions and data size.
  for (int d = 0; d < 8; ++d)
    image.niftiDim[d] = fields->wide ? h.get<std::int64_t>(fields->dim + 8 * d)
                                     : static_cast<std::int64_t>(h.get<std::int16_t>(fields->dim + 2 * d));
  const std::int64_t dims = image.niftiDim[0];
  if (dims < 1 || dims > 7) throw ImageIoError(path, "dim[0] is " + std::to_string(dims) + " (1 to 7 dimensions)");
  image.elementCount = 1;
  for (int d = 1; d <= dims; ++d) {
    if (image.niftiDim[d] < 1)
      throw ImageIoError(path, "dim[" + std::to_string(d) + "] is " + std::to_string(image.niftiDim[d]) +
                                   " (a size must be at least 1)");
    if (!multiply(image.elementCount, static_cast<std::uint64_t>(image.niftiDim[d]), image.elementCount))
      throw ImageIoError(path, "the sizes of the header overflow 64 bits");
  }
  image.niftiDatatype = fields->wide ? h.get<std::int16_t>(fields->datatype) : h.get<std::int16_t>(fields->datatype);
  image.elementBytes = niftiDatatypeBytes(image.niftiDatatype);
  if (image.elementBytes == 0)
    throw ImageIoError(path, "unknown NIfTI datatype " + std::to_string(image.niftiDatatype));
  std::uint64_t dataBytes;
  if (!multiply(image.elementCount, image.elementBytes, dataBytes))
    throw ImageIoError(path, "the data size of the header overflows 64 bits");

  const double voxOffset = fields->wide ? static_cast<double>(h.get<std::int64_t>(fields->voxOffset))
                                        : real(fields->voxOffset);
  if (!(voxOffset >= 0) || voxOffset > 9e15)
    throw ImageIoError(path, "vox_offset is " + number(voxOffset));
  image.dataOffset = static_cast<std::uint64_t>(voxOffset);
  if (!pair) image.dataOffset = std::max<std::uint64_t>(image.dataOffset, fields->headerSize);
  std::uint64_t needed;
  if (__builtin_add_overflow(image.dataOffset, dataBytes, &needed))
    throw ImageIoError(path, "the data size of the header overflows 64 bits");

  // Geometry: the spacings of every axis, and the qform and sform when their
  // codes say they are used.
  for (int d = 1; d <= dims; ++d)
    checkCoordinate(real(fields->pixdim + (fields->wide ? 8 : 4) * d), "pixdim[" + std::to_string(d) + "]", path);
  const double qfac = real(fields->pixdim);
  if (!std::isfinite(qfac)) throw ImageIoError(path, "pixdim[0] (qfac) is not a finite number");
  const double slope = real(fields->sclSlope), intercept = real(fields->sclInter);
  if (!std::isfinite(slope) || (slope != 0 && !std::isfinite(intercept)))
    throw ImageIoError(path, "the scaling scl_slope " + number(slope) + ", scl_inter " + number(intercept) +
                                 " is not finite");
  {  // checked whatever the magic says: a library may still use them
    const std::size_t step = fields->wide ? 8 : 4;
    if (code(fields->qformCode) > 0) {
      const char* names[6] = {"quatern_b", "quatern_c", "quatern_d", "qoffset_x", "qoffset_y", "qoffset_z"};
      for (int q = 0; q < 6; ++q) checkCoordinate(real(fields->quatern + step * q), names[q], path);
    }
    if (code(fields->sformCode) > 0) {
      const char axes[3] = {'x', 'y', 'z'};
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 4; ++c)
          checkCoordinate(real(fields->srow + step * (4 * r + c)),
                          std::string("srow_") + axes[r] + "[" + std::to_string(c) + "]", path);
    }
  }

  image.gzipData = endsWith(lowercase(image.dataPath), ".gz");
  // The header alone (a side input's grid): the data file must be a
  // regular file, but what its data need is checked only when they are read.
  const std::uint64_t fileBytes = regularFileSize(image.dataPath, path, "the image file");
  if (!withData) return image;
  checkValuesFitInMemory(image.elementCount, image.elementBytes, path);
  if (image.gzipData) {
    checkGzipHolds(image.dataPath, 0, fileBytes, needed, path);
  } else if (fileBytes < needed) {
    throw ImageIoError(path, "the file is truncated: " + std::to_string(fileBytes) +
                                 " bytes where header and data need " + std::to_string(needed));
  }
  return image;
}

// --- NRRD -------------------------------------------------------------------

/// The field's canonical name (NRRD0005's fields and the spellings NrrdIO
/// takes for them, already lower case), or "" for no NRRD field.
std::string canonicalNrrdField(const std::string& name) {
  static const std::pair<const char*, const char*> fields[] = {
      {"content", "content"},
      {"number", "number"},
      {"type", "type"},
      {"block size", "block size"},
      {"blocksize", "block size"},
      {"dimension", "dimension"},
      {"space", "space"},
      {"space dimension", "space dimension"},
      {"spacedimension", "space dimension"},
      {"sizes", "sizes"},
      {"spacings", "spacings"},
      {"thicknesses", "thicknesses"},
      {"axis mins", "axis mins"},
      {"axismins", "axis mins"},
      {"axis maxs", "axis maxs"},
      {"axismaxs", "axis maxs"},
      {"space directions", "space directions"},
      {"spacedirections", "space directions"},
      {"centers", "centers"},
      {"centerings", "centers"},
      {"kinds", "kinds"},
      {"labels", "labels"},
      {"units", "units"},
      {"min", "min"},
      {"max", "max"},
      {"old min", "old min"},
      {"oldmin", "old min"},
      {"old max", "old max"},
      {"oldmax", "old max"},
      {"endian", "endian"},
      {"encoding", "encoding"},
      {"line skip", "line skip"},
      {"lineskip", "line skip"},
      {"byte skip", "byte skip"},
      {"byteskip", "byte skip"},
      {"sample units", "sample units"},
      {"sampleunits", "sample units"},
      {"space units", "space units"},
      {"spaceunits", "space units"},
      {"space origin", "space origin"},
      {"spaceorigin", "space origin"},
      {"measurement frame", "measurement frame"},
      {"measurementframe", "measurement frame"},
      {"data file", "data file"},
      {"datafile", "data file"},
  };
  for (const auto& [spelling, canonical] : fields)
    if (name == spelling) return canonical;
  return {};
}

unsigned nrrdTypeBytes(const std::string& type) {
  static const std::pair<const char*, unsigned> names[] = {
      {"signed char", 1}, {"int8", 1}, {"int8_t", 1}, {"uchar", 1}, {"unsigned char", 1}, {"uint8", 1},
      {"uint8_t", 1}, {"short", 2}, {"short int", 2}, {"signed short", 2}, {"signed short int", 2},
      {"int16", 2}, {"int16_t", 2}, {"ushort", 2}, {"unsigned short", 2}, {"unsigned short int", 2},
      {"uint16", 2}, {"uint16_t", 2}, {"int", 4}, {"signed int", 4}, {"int32", 4}, {"int32_t", 4},
      {"uint", 4}, {"unsigned int", 4}, {"uint32", 4}, {"uint32_t", 4}, {"longlong", 8}, {"long long", 8},
      {"long long int", 8}, {"signed long long", 8}, {"signed long long int", 8}, {"int64", 8},
      {"int64_t", 8}, {"ulonglong", 8}, {"unsigned long long", 8}, {"unsigned long long int", 8},
      {"uint64", 8}, {"uint64_t", 8}, {"float", 4}, {"double", 8}};
  for (const auto& [name, bytes] : names)
    if (type == name) return bytes;
  return 0;
}

std::string trim(const std::string& s) {
  const std::size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  return s.substr(a, s.find_last_not_of(" \t\r") - a + 1);
}

std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> out;
  for (std::string w; in >> w;) out.push_back(w);
  return out;
}

bool parseInteger(const std::string& t, long long& value) {
  errno = 0;
  char* end = nullptr;
  value = std::strtoll(t.c_str(), &end, 10);
  return end != t.c_str() && *end == '\0' && errno == 0;
}

/// Every number inside the parentheses of a vector list such as
/// "(1,0,0) none (0,1.5,0)": finite and within kMaxCoordinateMm.
void checkVectors(const std::string& value, const std::string& field, const std::string& reportedPath) {
  std::string current;
  bool inside = false;
  auto flush = [&] {
    const std::string t = trim(current);
    current.clear();
    char* end = nullptr;
    const double x = std::strtod(t.c_str(), &end);
    if (t.empty() || end == t.c_str() || trim(end) != "")
      throw ImageIoError(reportedPath, "\"" + field + "\" holds \"" + t + "\", which is not a number");
    checkCoordinate(x, "a \"" + field + "\" value", reportedPath);
  };
  for (char c : value) {
    if (c == '(') {
      if (inside) throw ImageIoError(reportedPath, "\"" + field + "\" has unbalanced parentheses");
      inside = true;
    } else if (c == ')') {
      if (!inside) throw ImageIoError(reportedPath, "\"" + field + "\" has unbalanced parentheses");
      flush();
      inside = false;
    } else if (c == ',' && inside) {
      flush();
    } else if (inside) {
      current += c;
    }
  }
  if (inside) throw ImageIoError(reportedPath, "\"" + field + "\" has unbalanced parentheses");
}

/// Scans ascii data for `count` values: each token at most
/// kMaxAsciiTokenLength characters, no NUL byte.
void checkAsciiData(const std::string& dataPath, std::uint64_t offset, std::uint64_t count,
                    const std::string& reportedPath) {
  std::ifstream in(dataPath, std::ios::binary);
  in.seekg(static_cast<std::streamoff>(offset));
  std::uint64_t found = 0;
  std::size_t length = 0;
  std::vector<char> buffer(1 << 16);
  while (found < count && in) {
    in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
    const std::streamsize n = in.gcount();
    for (std::streamsize i = 0; i < n && found < count; ++i) {
      const char c = buffer[static_cast<std::size_t>(i)];
      if (c == '\0') throw ImageIoError(reportedPath, "the ascii data hold a NUL byte");
      if (std::isspace(static_cast<unsigned char>(c)) || c == ',') {
        if (length > 0) ++found;
        length = 0;
      } else if (++length > kMaxAsciiTokenLength) {
        throw ImageIoError(reportedPath, "value " + std::to_string(found + 1) + " of the ascii data is longer than " +
                                             std::to_string(kMaxAsciiTokenLength) + " characters");
      }
    }
  }
  if (length > 0 && found < count) ++found;
  if (found < count)
    throw ImageIoError(reportedPath, "the ascii data hold " + std::to_string(found) + " values where the header needs " +
                                         std::to_string(count));
}

ScreenedImage screenNrrd(const std::string& path, bool withData) {
  ScreenedImage image;
  image.format = ImageFileFormat::Nrrd;
  const std::uint64_t headerFileBytes = regularFileSize(path, path, "the file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ImageIoError(path, std::string("cannot open: ") + std::strerror(errno));
  std::string line;
  std::uint64_t consumed = 0;
  auto nextLine = [&]() {
    line.clear();
    char c;
    bool any = false;
    while (in.get(c)) {
      any = true;
      ++consumed;
      if (c == '\n') break;
      if (c == '\0') throw ImageIoError(path, "the NRRD header holds a NUL byte");
      line += c;
      if (consumed > kMaxNrrdHeaderBytes)
        throw ImageIoError(path, "the NRRD header is longer than " + std::to_string(kMaxNrrdHeaderBytes) + " bytes");
    }
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return any;
  };
  if (!nextLine() || line.size() != 8 || line.compare(0, 7, "NRRD000") != 0 || line[7] < '1' || line[7] > '5')
    throw ImageIoError(path, "not a NRRD file (it does not start with NRRD0001 to NRRD0005)");

  long long dimension = -1, lineSkip = 0, byteSkip = 0;
  std::vector<std::string> sizes;
  std::string type, encoding = "", dataFile;
  std::set<std::string> seenFields;
  bool attachedData = false;
  while (nextLine()) {
    if (line.empty()) {
      attachedData = true;
      break;
    }
    if (line[0] == '#') continue;
    if (line.find(":=") != std::string::npos && line.find(":=") < line.find(": ")) continue;  // key/value pair
    const std::size_t colon = line.find(": ");
    if (colon == std::string::npos) throw ImageIoError(path, "NRRD header line \"" + line.substr(0, 60) + "\" has no \": \"");
    const std::string field = canonicalNrrdField(lowercase(trim(line.substr(0, colon))));
    // What NrrdIO refuses is refused here, before ITK sees the header: an
    // unknown field, a field given twice (NrrdIO refuses the second only
    // after it has parsed the first, which this screen would otherwise not
    // have checked) and a line long enough that NrrdIO's message about a value
    // it cannot parse overflows a stack buffer.
    if (field.empty()) throw ImageIoError(path, "\"" + line.substr(0, std::min<std::size_t>(colon, 60)) + "\" is not a NRRD field");
    if (!seenFields.insert(field).second) throw ImageIoError(path, "the NRRD field \"" + field + "\" is given twice");
    if (line.size() > kMaxNrrdFieldLineLength && field != "content" && field != "data file")
      throw ImageIoError(path, "the NRRD field \"" + field + "\" is longer than " +
                                   std::to_string(kMaxNrrdFieldLineLength) + " bytes");
    const std::string value = trim(line.substr(colon + 2));
    if (field == "dimension") {
      if (!parseInteger(value, dimension) || dimension < 1 || dimension > 16)
        throw ImageIoError(path, "dimension \"" + value + "\" is not 1 to 16");
    } else if (field == "type") {
      type = lowercase(value);
    } else if (field == "sizes") {
      sizes = words(value);
    } else if (field == "encoding") {
      encoding = lowercase(value);
    } else if (field == "line skip") {
      if (!parseInteger(value, lineSkip) || lineSkip < 0)
        throw ImageIoError(path, "line skip \"" + value + "\" is not a count of lines");
    } else if (field == "byte skip") {
      if (!parseInteger(value, byteSkip) || byteSkip < -1)
        throw ImageIoError(path, "byte skip \"" + value + "\" is not a count of bytes (or -1)");
    } else if (field == "data file") {
      dataFile = value;
    } else if (field == "space directions" || field == "space origin" || field == "measurement frame") {
      checkVectors(value, field, path);
    } else if (field == "spacings") {
      for (const std::string& w : words(value)) {
        if (lowercase(w) == "nan") continue;  // NRRD's "no spacing" for a non-spatial axis
        char* end = nullptr;
        const double x = std::strtod(w.c_str(), &end);
        if (end == w.c_str() || *end != '\0') throw ImageIoError(path, "spacing \"" + w + "\" is not a number");
        checkCoordinate(x, "a spacing", path);
      }
    }
  }
  if (dimension < 0) throw ImageIoError(path, "the NRRD header has no dimension");
  if (type.empty()) throw ImageIoError(path, "the NRRD header has no type");
  if (type == "block") throw ImageIoError(path, "NRRD type block is not supported");
  image.elementBytes = nrrdTypeBytes(type);
  if (image.elementBytes == 0) throw ImageIoError(path, "unknown NRRD type \"" + type + "\"");
  if (static_cast<long long>(sizes.size()) != dimension)
    throw ImageIoError(path, "sizes gives " + std::to_string(sizes.size()) + " sizes for dimension " +
                                 std::to_string(dimension));
  image.elementCount = 1;
  for (const std::string& s : sizes) {
    long long n;
    if (!parseInteger(s, n) || n < 1) throw ImageIoError(path, "size \"" + s + "\" is not a positive integer");
    if (!multiply(image.elementCount, static_cast<std::uint64_t>(n), image.elementCount))
      throw ImageIoError(path, "the sizes of the header overflow 64 bits");
  }
  std::uint64_t dataBytes;
  if (!multiply(image.elementCount, image.elementBytes, dataBytes))
    throw ImageIoError(path, "the data size of the header overflows 64 bits");
  const bool raw = encoding == "raw", ascii = encoding == "txt" || encoding == "text" || encoding == "ascii";
  const bool hex = encoding == "hex", gzip = encoding == "gz" || encoding == "gzip";
  if (encoding.empty()) throw ImageIoError(path, "the NRRD header has no encoding");
  if (encoding == "bz2" || encoding == "bzip2")
    throw ImageIoError(path, "bzip2-compressed NRRD data are not supported (use raw or gzip)");
  if (!raw && !ascii && !hex && !gzip) throw ImageIoError(path, "unknown NRRD encoding \"" + encoding + "\"");
  if (byteSkip == -1 && !raw) throw ImageIoError(path, "byte skip -1 needs raw encoding");
  if (withData) checkValuesFitInMemory(image.elementCount, image.elementBytes, path);

  // Where the data are: after the header's blank line, or in the data file.
  std::uint64_t offset = consumed;
  if (!dataFile.empty()) {
    const std::vector<std::string> w = words(dataFile);
    if (w.size() != 1 || w[0] == "LIST" || w[0].find('%') != std::string::npos)
      throw ImageIoError(path, "data spread over several files (\"data file: " + dataFile.substr(0, 60) +
                                   "\") is not supported");
    const std::size_t slash = path.find_last_of('/');
    image.dataPath = w[0][0] == '/' || slash == std::string::npos ? w[0] : path.substr(0, slash + 1) + w[0];
    offset = 0;
  } else {
    if (!attachedData && endsWith(lowercase(path), ".nhdr"))
      throw ImageIoError(path, "a detached NRRD header without a \"data file\" field");
    image.dataPath = path;
  }
  const std::uint64_t fileBytes =
      dataFile.empty() ? headerFileBytes : regularFileSize(image.dataPath, path, "the data file");
  if (lineSkip > 0) {  // NrrdIO skips the lines when it reads the header: checked even for the header alone
    std::ifstream data(image.dataPath, std::ios::binary);
    data.seekg(static_cast<std::streamoff>(offset));
    long long lines = 0;
    char c;
    while (lines < lineSkip && data.get(c)) {
      ++offset;
      if (c == '\n') ++lines;
    }
    if (lines < lineSkip)
      throw ImageIoError(path, "line skip " + std::to_string(lineSkip) + " goes beyond the end of the data file");
  }
  if (byteSkip > 0 && !gzip) offset += static_cast<std::uint64_t>(byteSkip);
  if (offset > fileBytes) throw ImageIoError(path, "byte skip " + std::to_string(byteSkip) + " goes beyond the end of the data file");
  const std::uint64_t available = fileBytes - offset;
  image.dataOffset = offset;
  image.gzipData = gzip;
  // The header alone (a side input's grid): what the data need is checked
  // only when they are read.
  if (!withData) return image;
  if (raw && available < dataBytes) {
    throw ImageIoError(path, "the data are truncated: " + std::to_string(available) + " bytes where the header needs " +
                                 std::to_string(dataBytes));
  } else if (hex && available / 2 < dataBytes) {
    throw ImageIoError(path, "the hex data are truncated: " + std::to_string(available) +
                                 " characters where the header needs " + std::to_string(2 * dataBytes));
  } else if (ascii) {
    checkAsciiData(image.dataPath, offset, image.elementCount, path);
  } else if (gzip) {
    std::uint64_t needed = dataBytes;
    if (byteSkip > 0 && __builtin_add_overflow(dataBytes, static_cast<std::uint64_t>(byteSkip), &needed))
      throw ImageIoError(path, "byte skip " + std::to_string(byteSkip) + " is out of range");
    checkGzipHolds(image.dataPath, offset, available, needed, path);
  }
  return image;
}

}  // namespace

ScreenedImage screenImageFile(const std::string& path, bool withData) {
  const std::string lower = lowercase(path);
  if (endsWith(lower, ".nrrd") || endsWith(lower, ".nhdr")) return screenNrrd(path, withData);
  for (const char* ext : {".nii", ".nii.gz", ".hdr", ".hdr.gz", ".img", ".img.gz"})
    if (endsWith(lower, ext)) return screenNifti(path, lower, withData);
  throw ImageIoError(path, "not a NIfTI (.nii, .nii.gz, .hdr/.img), NRRD (.nrrd, .nhdr) or MRtrix (.mif, .mif.gz, "
                           ".mih) file name");
}

std::vector<NonFiniteValue> nonFiniteNiftiValues(const ScreenedImage& image, const std::string& path) {
  std::vector<NonFiniteValue> indices;
  const bool f32 = image.niftiDatatype == 16, f64 = image.niftiDatatype == 64;
  if (image.format != ImageFileFormat::Nifti || (!f32 && !f64)) return indices;
  const GzFile f = openAt(image.dataPath, 0, path);
  if (gzseek(f.get(), static_cast<z_off_t>(image.dataOffset), SEEK_SET) < 0)
    throw ImageIoError(path, "cannot read the image data");
  const unsigned size = f64 ? 8 : 4;
  std::vector<unsigned char> buffer(std::size_t{1} << 16);
  std::uint64_t index = 0;
  while (index < image.elementCount) {
    const std::uint64_t want = std::min<std::uint64_t>(buffer.size() / size, image.elementCount - index);
    const int n = gzread(f.get(), buffer.data(), static_cast<unsigned>(want * size));
    if (n != static_cast<int>(want * size)) throw ImageIoError(path, "cannot read the image data (truncated?)");
    for (std::uint64_t k = 0; k < want; ++k) {
      unsigned char* raw = buffer.data() + k * size;
      if (image.niftiSwapped) std::reverse(raw, raw + size);
      double x;
      if (f64) {
        std::memcpy(&x, raw, 8);
      } else {
        float y;
        std::memcpy(&y, raw, 4);
        x = y;
      }
      if (!std::isfinite(x)) indices.push_back({index + k, x});
    }
    index += want;
  }
  return indices;
}

std::vector<unsigned char> threeDimensionalNiftiHeader(const ScreenedImage& image) {
  std::vector<unsigned char> header = image.niftiHeader;
  const bool wide = image.niftiVersion == 2;
  const NiftiFields& f = wide ? kNifti2 : kNifti1;
  const std::int64_t dim[8] = {3, image.niftiDim[1], image.niftiDim[2], image.niftiDim[3], 1, 1, 1, 1};
  for (int d = 0; d < 8; ++d) {
    if (wide)
      put<std::int64_t>(header, f.dim + 8 * d, dim[d], image.niftiSwapped);
    else
      put<std::int16_t>(header, f.dim + 2 * d, static_cast<std::int16_t>(dim[d]), image.niftiSwapped);
  }
  if (wide) {
    put<std::int32_t>(header, f.intentCode, 0, image.niftiSwapped);
    put<std::int64_t>(header, f.voxOffset, 544, image.niftiSwapped);
    std::memcpy(header.data() + 4, "n+2\0\r\n\032\n", 8);
  } else {
    put<std::int16_t>(header, f.intentCode, 0, image.niftiSwapped);
    put<float>(header, f.voxOffset, 352.f, image.niftiSwapped);
    std::memcpy(header.data() + 344, "n+1\0", 4);
  }
  return header;
}

}  // namespace stvd::imaging::detail
