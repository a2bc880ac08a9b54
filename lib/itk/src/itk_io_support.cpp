#include "itk_io_support.hpp"

#include <itkImageIOFactory.h>
#include <itkNiftiImageIOFactory.h>
#include <itkNrrdImageIOFactory.h>

#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <stdexcept>

#include "stvd/itk/image_io_error.hpp"

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
  if (line.size() > 240) line = line.substr(0, 237) + "...";
  return line;
}

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
    throw ImageIoError(path, "not a readable NIfTI (.nii, .nii.gz) or NRRD (.nrrd, .nhdr) image "
                             "(unknown format, or a damaged header)");
  io->SetFileName(path);
  try {
    io->ReadImageInformation();
  } catch (const std::exception& e) {
    throw ImageIoError(path, "cannot read the header: " + conciseItkMessage(e));
  }
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
