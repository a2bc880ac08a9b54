#include "itk_io_support.hpp"
#include "nrrd_header.hpp"

#include <itkImageIOFactory.h>
#include <itkMetaDataObject.h>
#include <itkNiftiImageIOFactory.h>
#include <itkNrrdImageIOFactory.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>

#include "library_messages.hpp"
#include "stvd/errors.hpp"
#include "stvd/system/files/regular_file.hpp"


namespace stvd::imaging::detail {

void registerImageIoFactories() {
  // Each RegisterOneFactory() call adds another copy of the factory, hence
  // the once-flag. Registering by hand spares users ITK's use-file.
  static std::once_flag once;
  std::call_once(once, [] {
    itk::NrrdImageIOFactory::RegisterOneFactory();
    itk::NiftiImageIOFactory::RegisterOneFactory();
  });
}

std::string conciseItkMessage(const std::exception& e) {
  std::string text;
  if (const auto* itkError = dynamic_cast<const itk::ExceptionObject*>(&e))
    text = itkError->GetDescription();
  else
    text = e.what();
  // ITK prefixes messages with class names and addresses and spreads them
  // over lines; keep the words, one line.
  std::string line;
  bool space = false;
  for (char c : text) {
    if (c == '\n' || c == '\r' || c == '\t' || c == ' ') {
      space = !line.empty();
      continue;
    }
    if (space) line += ' ';
    space = false;
    line += c;
  }
  // "ITK ERROR: NrrdImageIO(0x55...): " says nothing to a user.
  if (line.rfind("ITK ERROR: ", 0) == 0) {
    const std::size_t colon = line.find("): ");
    if (colon != std::string::npos) line = line.substr(colon + 3);
  }
  // NRRD errors are a chain "[nrrd] f: trouble [nrrd] g: ... [nrrd] h: cause";
  // the last link names the cause.
  const std::size_t last = line.rfind("[nrrd] ");
  if (last != std::string::npos && last > 0) line = line.substr(last + 7);
  if (line.size() > 240) line = line.substr(0, 237) + "...";
  return line;
}

OpenedImage openImageForReading(const std::string& path, bool withData) {
  registerImageIoFactories();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw ImageIoError(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) throw ImageIoError(path, "is a folder, not an image file");
  try {  // opened without blocking: a FIFO or a device named like an image is refused, not read for ever
    const files::RegularFile probe(path);
    if (probe.size() == 0) throw ImageIoError(path, "the file is empty");
  } catch (const files::InputFileError& e) {
    throw ImageIoError(path, e.problem());
  }
  OpenedImage image;
  image.screened = screenImageFile(path, withData);
  LibraryMessageCapture quiet;
  image.io = itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::IOFileModeEnum::ReadMode);
  if (!image.io)
    throw ImageIoError(path, "not a readable NIfTI (.nii, .nii.gz) or NRRD (.nrrd, .nhdr) image "
                             "(unknown format, or a damaged header)");
  image.io->SetFileName(path);
  try {
    image.io->ReadImageInformation();
  } catch (const std::exception& e) {
    throw ImageIoError(path, "cannot read the header: " + conciseItkMessage(e));
  }
  return image;
}

namespace {

GridGeometry geometryOfAxes(itk::ImageIOBase& io, const std::string& path) {
  GridGeometry g;
  const unsigned dims = io.GetNumberOfDimensions();
  for (unsigned a = 0; a < 3; ++a) {
    if (a < dims) {
      g.size[a] = io.GetDimensions(a);
      g.spacing[a] = io.GetSpacing(a);
      g.origin[a] = io.GetOrigin(a);
      const std::vector<double> column = io.GetDirection(a);
      for (unsigned r = 0; r < 3; ++r) g.direction[3 * r + a] = r < column.size() ? column[r] : 0.0;
    } else {
      g.size[a] = 1;
      g.spacing[a] = 1.0;
      g.origin[a] = 0.0;
      for (unsigned r = 0; r < 3; ++r) g.direction[3 * r + a] = r == a ? 1.0 : 0.0;
    }
  }
  // A NRRD space left-anterior-superior differs from LPS in y alone, but ITK
  // 5.2's NrrdImageIO converts it as if x were flipped (its LAS case negates
  // the x of every axis and of the origin), which mirrors the grid: seen on a
  // hand-made file, origin (10, 20, 30) LAS came out as LPS (-10, 20, 30)
  // instead of (10, -20, 30). Undo that and apply the y flip: negate x and y.
  // (nrrd_header.cpp converts the tensor components with the same, right,
  // diag(1, -1, 1); tests/itk/hand_made_files_test.cpp holds both.) The
  // space is read from the header: ITK's dictionary does not keep it.
  if (std::string(io.GetNameOfClass()) == "NrrdImageIO" && nrrdSpaceIsLeftAnteriorSuperior(path)) {
    for (int c = 0; c < 3; ++c) {
      g.direction[c] = -g.direction[c];
      g.direction[3 + c] = -g.direction[3 + c];
    }
    g.origin[0] = -g.origin[0];
    g.origin[1] = -g.origin[1];
  }
  try {
    g.validate();
  } catch (const std::invalid_argument& e) {
    throw ImageIoError(path, std::string("unusable image geometry: ") + e.what());
  }
  // Positions far from the origin of the scanner lose the precision that
  // paths and seeds need; the header screening refuses them already for
  // NIfTI and NRRD headers, this catches whatever ITK derives.
  for (int a = 0; a < 3; ++a)
    if (!(std::abs(g.origin[a]) <= kMaxCoordinateMm))
      throw ImageIoError(path, "the origin lies beyond the " + std::to_string(static_cast<long>(kMaxCoordinateMm)) +
                                   " mm that stvd accepts");
  return g;
}

/// The geometry ITK reads from `header` as a 3D file: a scratch .nii of the
/// header alone, read for its information only. The scratch file is a new
/// file of a random name (mkstemps: O_EXCL, mode 0600), never one that
/// someone put in the shared temporary folder under a name we would use.
GridGeometry threeDimensionalGeometry(const std::vector<unsigned char>& header, const std::string& path) {
  std::error_code ec;
  std::string pattern = (std::filesystem::temp_directory_path(ec) / "stvd-header-XXXXXX.nii").string();
  const int fd = ::mkstemps(pattern.data(), 4);
  if (fd < 0) throw ImageIoError(path, "cannot make a scratch file in the temporary folder: " + std::string(std::strerror(errno)));
  const std::filesystem::path scratch = pattern;
  struct Remove {
    std::filesystem::path p;
    ~Remove() {
      std::error_code ec;
      std::filesystem::remove(p, ec);
    }
  } remove{scratch};
  {
    std::string bytes(header.begin(), header.end());
    bytes.append(4, '\0');  // no extension
    std::size_t done = 0;
    while (done < bytes.size()) {
      const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) break;
      done += static_cast<std::size_t>(n);
    }
    if (::close(fd) != 0 || done != bytes.size())
      throw ImageIoError(path, "cannot write a scratch file in " + scratch.parent_path().string());
  }
  LibraryMessageCapture quiet;
  itk::ImageIOBase::Pointer io = itk::ImageIOFactory::CreateImageIO(scratch.c_str(), itk::IOFileModeEnum::ReadMode);
  if (!io) throw ImageIoError(path, "cannot read the geometry of the header");
  io->SetFileName(scratch.string());
  try {
    io->ReadImageInformation();
  } catch (const std::exception& e) {
    throw ImageIoError(path, "cannot read the geometry of the header: " + conciseItkMessage(e));
  }
  if (io->GetNumberOfDimensions() != 3) throw ImageIoError(path, "cannot read the geometry of the header");
  return geometryOfAxes(*io, path);
}

}  // namespace

GridGeometry geometryOf(const OpenedImage& image, const std::string& path) {
  itk::ImageIOBase& io = *image.io;
  // ITK drops the third axis of a 5D tensor NIfTI of one slice, its
  // spacing and origin with it; a 3D copy of the header keeps them.
  if (image.isNifti() && image.screened.niftiVersion > 0 && io.GetNumberOfDimensions() < 3 &&
      image.screened.niftiDim[0] >= 3) {
    const GridGeometry g = threeDimensionalGeometry(threeDimensionalNiftiHeader(image.screened), path);
    for (unsigned a = 0; a < io.GetNumberOfDimensions(); ++a)
      if (g.size[a] != io.GetDimensions(a)) throw ImageIoError(path, "cannot read the geometry of the header");
    return g;
  }
  return geometryOfAxes(io, path);
}

namespace {

template <class T>
void convertComponents(const char* raw, std::size_t count, std::vector<float>& out) {
  out.resize(count);
  for (std::size_t n = 0; n < count; ++n) {
    T value;
    std::memcpy(&value, raw + n * sizeof(T), sizeof(T));
    out[n] = static_cast<float>(value);
  }
}

/// Puts back the values (a float or double buffer in ITK's order) that the
/// file holds as NaN or infinity and niftilib replaced by 0. With several
/// components per pixel (interleaved by ITK, one volume per component in
/// the file), the whole pixel becomes NaN.
template <class T>
void restoreNonFinite(RawComponents& raw, const std::vector<NonFiniteValue>& values, std::size_t components) {
  const std::size_t pixels = raw.count / components;
  T* buffer = reinterpret_cast<T*>(raw.bytes.data());
  for (const NonFiniteValue& v : values) {
    if (components == 1) {
      if (v.index < raw.count) buffer[v.index] = static_cast<T>(v.value);
      continue;
    }
    const std::size_t pixel = static_cast<std::size_t>(v.index % pixels);
    for (std::size_t c = 0; c < components; ++c) buffer[pixel * components + c] = std::numeric_limits<T>::quiet_NaN();
  }
}

}  // namespace

RawComponents readRawComponents(OpenedImage& image, const std::string& path) {
  itk::ImageIOBase& io = *image.io;
  const unsigned dims = io.GetNumberOfDimensions();
  itk::ImageIORegion region(dims);
  std::size_t pixels = 1;
  for (unsigned d = 0; d < dims; ++d) {
    region.SetIndex(d, 0);
    region.SetSize(d, io.GetDimensions(d));
    pixels *= io.GetDimensions(d);
  }
  io.SetIORegion(region);
  RawComponents raw;
  raw.type = io.GetComponentType();
  raw.count = pixels * io.GetNumberOfComponents();
  raw.bytes.resize(raw.count * io.GetComponentSize());
  try {
    LibraryMessageCapture quiet;
    io.Read(raw.bytes.data());
  } catch (const std::exception& e) {
    throw ImageIoError(path, "cannot read the image data (truncated or damaged file?): " +
                                 conciseItkMessage(e));
  }
  if (image.isNifti() && (raw.type == itk::IOComponentEnum::FLOAT || raw.type == itk::IOComponentEnum::DOUBLE)) {
    const std::vector<NonFiniteValue> nonFinite = nonFiniteNiftiValues(image.screened, path);
    const std::size_t components = io.GetNumberOfComponents();
    if (raw.type == itk::IOComponentEnum::FLOAT)
      restoreNonFinite<float>(raw, nonFinite, components);
    else
      restoreNonFinite<double>(raw, nonFinite, components);
  }
  return raw;
}

std::vector<float> readAllComponents(OpenedImage& image, const std::string& path) {
  const RawComponents raw = readRawComponents(image, path);
  const std::size_t count = raw.count;
  const char* bytes = raw.bytes.data();
  std::vector<float> out;
  using C = itk::IOComponentEnum;
  switch (raw.type) {
    case C::UCHAR: convertComponents<std::uint8_t>(bytes, count, out); break;
    case C::CHAR: convertComponents<std::int8_t>(bytes, count, out); break;
    case C::USHORT: convertComponents<std::uint16_t>(bytes, count, out); break;
    case C::SHORT: convertComponents<std::int16_t>(bytes, count, out); break;
    case C::UINT: convertComponents<std::uint32_t>(bytes, count, out); break;
    case C::INT: convertComponents<std::int32_t>(bytes, count, out); break;
    case C::ULONG: convertComponents<unsigned long>(bytes, count, out); break;
    case C::LONG: convertComponents<long>(bytes, count, out); break;
    case C::ULONGLONG: convertComponents<unsigned long long>(bytes, count, out); break;
    case C::LONGLONG: convertComponents<long long>(bytes, count, out); break;
    case C::FLOAT: convertComponents<float>(bytes, count, out); break;
    case C::DOUBLE: convertComponents<double>(bytes, count, out); break;
    default:
      throw ImageIoError(path, "unsupported component type " + itk::ImageIOBase::GetComponentTypeAsString(raw.type));
  }
  return out;
}

itk::ImageIOBase::Pointer createFloatWriter(const std::string& path, const std::string& reportedPath,
                                            const GridGeometry& geometry, unsigned components,
                                            itk::IOPixelEnum pixelType, unsigned extraAxis) {
  registerImageIoFactories();
  itk::ImageIOBase::Pointer io =
      itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::IOFileModeEnum::WriteMode);
  if (!io)
    throw ImageIoError(reportedPath, "unsupported output format (use .nii, .nii.gz, .nrrd or .nhdr)");
  const unsigned dims = extraAxis > 0 ? 4 : 3;
  io->SetNumberOfDimensions(dims);
  for (unsigned a = 0; a < dims; ++a) {
    std::vector<double> column(dims, 0.0);
    if (a < 3) {
      io->SetDimensions(a, static_cast<unsigned>(geometry.size[a]));
      io->SetSpacing(a, geometry.spacing[a]);
      io->SetOrigin(a, geometry.origin[a]);
      for (unsigned r = 0; r < 3; ++r) column[r] = geometry.direction[3 * r + a];
    } else {
      io->SetDimensions(a, extraAxis);
      io->SetSpacing(a, 1.0);
      io->SetOrigin(a, 0.0);
      column[a] = 1.0;
    }
    io->SetDirection(a, column);
  }
  io->SetComponentType(itk::IOComponentEnum::FLOAT);
  io->SetPixelType(pixelType);
  io->SetNumberOfComponents(components);
  io->SetUseCompression(true);
  io->SetFileName(path);
  itk::ImageIORegion region(dims);
  for (unsigned a = 0; a < dims; ++a) {
    region.SetIndex(a, 0);
    region.SetSize(a, io->GetDimensions(a));
  }
  io->SetIORegion(region);
  return io;
}

void writeFloatData(itk::ImageIOBase& io, const std::string& reportedPath, const float* data) {
  LibraryMessageCapture quiet;
  try {
    io.Write(data);
  } catch (const std::exception& e) {
    throw ImageIoError(reportedPath, "cannot write: " + conciseItkMessage(e));
  }
  // niftilib reports a failed write ("** ERROR: NWAD: wrote only 0 of ...
  // bytes") on standard error without ITK throwing; standard error is not
  // ours to read (library_messages.hpp), and checkWrittenImage finds the
  // short file instead (written_files.hpp).
}

}  // namespace stvd::imaging::detail
