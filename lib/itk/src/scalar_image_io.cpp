#include "stvd/itk/scalar_image_io.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <sstream>

#include "itk_io_support.hpp"
#include "stvd/errors.hpp"
#include "stvd/imaging/detail/image_output.hpp"
#include "stvd/imaging/detail/read_progress.hpp"
#include "stvd/imaging/image_files.hpp"
#include "stvd/imaging/label_values.hpp"
#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/system/files/output_transaction.hpp"
#include "written_files.hpp"

namespace stvd::imaging {

namespace {

detail::OpenedImage openScalarImage(const std::string& path) {
  detail::OpenedImage image = detail::openImageForReading(path);
  itk::ImageIOBase& io = *image.io;
  if (io.GetNumberOfComponents() != 1)
    throw ImageIoError(path, "not a scalar image: " + std::to_string(io.GetNumberOfComponents()) +
                                 " components per voxel");
  for (unsigned d = 3; d < io.GetNumberOfDimensions(); ++d)
    if (io.GetDimensions(d) != 1)
      throw ImageIoError(path, "not a 3D scalar image: axis " + std::to_string(d + 1) + " has " +
                                   std::to_string(io.GetDimensions(d)) + " samples");
  return image;
}

template <class T>
void integerLabels(const detail::RawComponents& raw, std::vector<std::int64_t>& labels, const std::string& path,
                   const GridGeometry& g, InterruptScope& progress) {
  labels.resize(raw.count);
  for (std::size_t v = 0; v < raw.count; ++v) {
    progress.step(raw.count + v);
    T value;
    std::memcpy(&value, raw.bytes.data() + v * sizeof(T), sizeof(T));
    if constexpr (std::is_unsigned_v<T> && sizeof(T) == 8)
      labels[v] = labelOfUnsigned64(value, path, g, v);
    else
      labels[v] = static_cast<std::int64_t>(value);
  }
}

template <class T>
void floatLabels(const detail::RawComponents& raw, std::vector<std::int64_t>& labels, const std::string& path,
                 const GridGeometry& g, InterruptScope& progress) {
  labels.resize(raw.count);
  for (std::size_t v = 0; v < raw.count; ++v) {
    progress.step(raw.count + v);
    T value;
    std::memcpy(&value, raw.bytes.data() + v * sizeof(T), sizeof(T));
    labels[v] = labelOfReal(static_cast<double>(value), path, g, v);
  }
}

/// An MRtrix image holds one volume: every axis after the third has size 1.
void checkMrtrixScalarImage(const MrtrixHeader& header, const std::string& path) {
  for (std::size_t a = 3; a < header.size.size(); ++a)
    if (header.size[a] != 1)
      throw ImageIoError(path, "not a 3D scalar image: axis " + std::to_string(a + 1) + " has " +
                                   std::to_string(header.size[a]) + " samples");
}

}  // namespace

ScalarImage readScalarImage(const std::string& path, Interrupter* interrupter) {
  InterruptScope progress(interrupter, "reading image", 0);
  ScalarImage image;
  if (isMrtrixImagePath(path)) {
    MrtrixImage mrtrix = detail::readMrtrixImage(path, progress);
    checkMrtrixScalarImage(mrtrix.header, path);
    image = {mrtrix.geometry, std::move(mrtrix.values), {}};
  } else {
    // One piece: ITK's read and the values' conversion to float.
    detail::OpenedImage opened = openScalarImage(path);
    image.geometry = detail::geometryOf(opened, path);
    image.values = detail::readAllComponents(opened, path);
    image.warnings = opened.screened.warnings;
  }
  progress.finish();
  return image;
}

LabelImage readLabelImage(const std::string& path, Interrupter* interrupter) {
  InterruptScope progress(interrupter, "reading labels", 0);
  if (isMrtrixImagePath(path)) {
    MrtrixLabelImage mrtrix = detail::readMrtrixLabelImage(path, progress);
    checkMrtrixScalarImage(mrtrix.header, path);
    progress.finish();
    return {mrtrix.geometry, std::move(mrtrix.labels), {}};
  }
  detail::OpenedImage opened = openScalarImage(path);
  LabelImage image;
  image.geometry = detail::geometryOf(opened, path);
  image.warnings = opened.screened.warnings;
  // Steps: the values read by ITK in one call, then a step per value
  // turned into a label.
  const detail::RawComponents raw = detail::readRawComponents(opened, path);
  progress.setTotal(2 * std::uint64_t(raw.count));
  progress.check(raw.count);
  const GridGeometry& g = image.geometry;
  using C = itk::IOComponentEnum;
  switch (raw.type) {
    case C::UCHAR: integerLabels<std::uint8_t>(raw, image.labels, path, g, progress); break;
    case C::CHAR: integerLabels<std::int8_t>(raw, image.labels, path, g, progress); break;
    case C::USHORT: integerLabels<std::uint16_t>(raw, image.labels, path, g, progress); break;
    case C::SHORT: integerLabels<std::int16_t>(raw, image.labels, path, g, progress); break;
    case C::UINT: integerLabels<std::uint32_t>(raw, image.labels, path, g, progress); break;
    case C::INT: integerLabels<std::int32_t>(raw, image.labels, path, g, progress); break;
    case C::ULONG: integerLabels<unsigned long>(raw, image.labels, path, g, progress); break;
    case C::LONG: integerLabels<long>(raw, image.labels, path, g, progress); break;
    case C::ULONGLONG: integerLabels<unsigned long long>(raw, image.labels, path, g, progress); break;
    case C::LONGLONG: integerLabels<long long>(raw, image.labels, path, g, progress); break;
    case C::FLOAT: floatLabels<float>(raw, image.labels, path, g, progress); break;
    case C::DOUBLE: floatLabels<double>(raw, image.labels, path, g, progress); break;
    default:
      throw ImageIoError(path, "unsupported component type " + itk::ImageIOBase::GetComponentTypeAsString(raw.type));
  }
  progress.finish();
  return image;
}

namespace {

void writeScalarImageTo(const std::string& stagingPath, const std::string& path, const GridGeometry& geometry,
                        const std::vector<float>& values) {
  if (values.size() != geometry.voxelCount())
    throw ImageIoError(path, std::to_string(values.size()) + " values for a grid of " +
                                 std::to_string(geometry.voxelCount()) + " voxels");
  checkImageOutputCompanions(path);
  if (isMrtrixImagePath(path)) {
    writeMrtrixImage(stagingPath, path, geometry, values);
  } else {
    itk::ImageIOBase::Pointer io =
        detail::createFloatWriter(stagingPath, path, geometry, 1, itk::IOPixelEnum::SCALAR);
    detail::writeFloatData(*io, path, values.data());
  }
  detail::checkWrittenImage(stagingPath, path, values);
}

}  // namespace

void writeScalarImage(const std::string& path, const GridGeometry& geometry,
                      const std::vector<float>& values) {
  detail::writeAtomically(
      path, [&](const std::string& staging) { writeScalarImageTo(staging, path, geometry, values); });
}

void writeScalarImage(files::OutputTransaction& outputs, const std::string& path, const GridGeometry& geometry,
                      const std::vector<float>& values) {
  outputs.write(path, [&](const std::string& staging) { writeScalarImageTo(staging, path, geometry, values); });
}

}  // namespace stvd::imaging
