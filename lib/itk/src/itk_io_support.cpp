#include "itk_io_support.hpp"

#include <itkImageIOFactory.h>
#include <itkMetaDataObject.h>
#include <itkNiftiImageIOFactory.h>
#include <itkNrrdImageIOFactory.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>

#include "stvd/itk/image_io_error.hpp"

#include <zlib.h>

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

namespace {

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// Bytes of a gzip file once decompressed, or -1 when the stream is damaged
/// or cut short.
long long gzipContentSize(const std::string& path) {
  gzFile file = gzopen(path.c_str(), "rb");
  if (!file) return -1;
  std::vector<char> buffer(1 << 20);
  long long total = 0;
  int n;
  while ((n = gzread(file, buffer.data(), static_cast<unsigned>(buffer.size()))) > 0) total += n;
  int error = Z_OK;
  gzerror(file, &error);
  gzclose(file);
  return (n < 0 || (error != Z_OK && error != Z_STREAM_END)) ? -1 : total;
}

/// ITK's NIfTI reader fills the missing part of a cut-short file silently,
/// so single-file NIfTI (.nii, .nii.gz) is checked here: the data must
/// reach vox_offset + voxels * bytes per voxel.
void checkNiftiDataIsComplete(itk::ImageIOBase& io, const std::string& path) {
  std::string lower = path;
  for (char& c : lower) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  const bool gzip = endsWith(lower, ".nii.gz");
  if (!gzip && !endsWith(lower, ".nii")) return;
  const itk::MetaDataDictionary& dict = io.GetMetaDataDictionary();
  auto number = [&](const std::string& key) {
    std::string text;
    if (!itk::ExposeMetaData<std::string>(dict, key, text)) return -1.0;
    return std::atof(text.c_str());
  };
  const double dims = number("dim[0]"), bitpix = number("bitpix"), offset = number("vox_offset");
  if (dims < 1 || bitpix <= 0 || offset < 0) return;
  double voxels = 1;
  for (int d = 1; d <= static_cast<int>(dims) && d <= 7; ++d) voxels *= std::max(1.0, number("dim[" + std::to_string(d) + "]"));
  const double expected = offset + voxels * bitpix / 8.0;
  double actual;
  if (gzip) {
    const long long size = gzipContentSize(path);
    if (size < 0) throw ImageIoError(path, "the compressed data are damaged or cut short");
    actual = static_cast<double>(size);
  } else {
    std::error_code ec;
    actual = static_cast<double>(std::filesystem::file_size(path, ec));
  }
  if (actual < expected)
    throw ImageIoError(path, "the file is truncated: " + std::to_string(static_cast<long long>(actual)) +
                                 " bytes where header and data need " +
                                 std::to_string(static_cast<long long>(expected)));
}

}  // namespace

itk::ImageIOBase::Pointer openImageForReading(const std::string& path) {
  registerImageIoFactories();
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) throw ImageIoError(path, "no such file");
  if (std::filesystem::is_directory(path, ec)) throw ImageIoError(path, "is a folder, not an image file");
  {
    std::ifstream probe(path, std::ios::binary);
    if (!probe) throw ImageIoError(path, std::string("cannot open: ") + std::strerror(errno));
    if (probe.peek() == std::ifstream::traits_type::eof()) throw ImageIoError(path, "the file is empty");
  }
  itk::ImageIOBase::Pointer io =
      itk::ImageIOFactory::CreateImageIO(path.c_str(), itk::IOFileModeEnum::ReadMode);
  if (!io)
    throw ImageIoError(path, "not a readable NIfTI (.nii, .nii.gz), NRRD (.nrrd, .nhdr) or MRtrix (.mif, "
                             ".mif.gz, .mih) image (unknown format, or a damaged header)");
  io->SetFileName(path);
  try {
    io->ReadImageInformation();
  } catch (const std::exception& e) {
    throw ImageIoError(path, "cannot read the header: " + conciseItkMessage(e));
  }
  if (std::string(io->GetNameOfClass()) == "NiftiImageIO") checkNiftiDataIsComplete(*io, path);
  return io;
}

GridGeometry geometryOf(itk::ImageIOBase& io, const std::string& path) {
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
  try {
    g.validate();
  } catch (const std::invalid_argument& e) {
    throw ImageIoError(path, std::string("unusable image geometry: ") + e.what());
  }
  return g;
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

}  // namespace

std::vector<float> readAllComponents(itk::ImageIOBase& io, const std::string& path) {
  const unsigned dims = io.GetNumberOfDimensions();
  itk::ImageIORegion region(dims);
  std::size_t pixels = 1;
  for (unsigned d = 0; d < dims; ++d) {
    region.SetIndex(d, 0);
    region.SetSize(d, io.GetDimensions(d));
    pixels *= io.GetDimensions(d);
  }
  io.SetIORegion(region);
  const std::size_t count = pixels * io.GetNumberOfComponents();
  std::vector<char> raw(count * io.GetComponentSize());
  try {
    io.Read(raw.data());
  } catch (const std::exception& e) {
    throw ImageIoError(path, "cannot read the image data (truncated or damaged file?): " +
                                 conciseItkMessage(e));
  }
  std::vector<float> out;
  using C = itk::IOComponentEnum;
  switch (io.GetComponentType()) {
    case C::UCHAR: convertComponents<std::uint8_t>(raw.data(), count, out); break;
    case C::CHAR: convertComponents<std::int8_t>(raw.data(), count, out); break;
    case C::USHORT: convertComponents<std::uint16_t>(raw.data(), count, out); break;
    case C::SHORT: convertComponents<std::int16_t>(raw.data(), count, out); break;
    case C::UINT: convertComponents<std::uint32_t>(raw.data(), count, out); break;
    case C::INT: convertComponents<std::int32_t>(raw.data(), count, out); break;
    case C::ULONG: convertComponents<unsigned long>(raw.data(), count, out); break;
    case C::LONG: convertComponents<long>(raw.data(), count, out); break;
    case C::ULONGLONG: convertComponents<unsigned long long>(raw.data(), count, out); break;
    case C::LONGLONG: convertComponents<long long>(raw.data(), count, out); break;
    case C::FLOAT: convertComponents<float>(raw.data(), count, out); break;
    case C::DOUBLE: convertComponents<double>(raw.data(), count, out); break;
    default:
      throw ImageIoError(path, "unsupported component type " +
                                   itk::ImageIOBase::GetComponentTypeAsString(io.GetComponentType()));
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
  try {
    io.Write(data);
  } catch (const std::exception& e) {
    throw ImageIoError(reportedPath, "cannot write: " + conciseItkMessage(e));
  }
}

}  // namespace stvd::imaging::detail
