#include "written_files.hpp"

#include <zlib.h>

#include <cctype>
#include <cstdint>
#include <cstring>

#include "itk_io_support.hpp"
#include "stvd/errors.hpp"
#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/system/files/output_transaction.hpp"

namespace stvd::imaging::detail {
namespace {

std::string lowerCase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

void checkNiftiSize(const std::string& path, const std::string& reportedPath, std::uint64_t dataBytes) {
  // zlib reads an uncompressed file as it is, so one loop serves both.
  gzFile file = gzopen(path.c_str(), "rb");
  if (!file) throw ImageIoError(reportedPath, "the written file cannot be opened to check it");
  unsigned char header[540] = {};
  std::uint64_t total = 0;
  std::vector<unsigned char> buffer(1 << 20);
  int n;
  while ((n = gzread(file, buffer.data(), static_cast<unsigned>(buffer.size()))) > 0) {
    if (total < sizeof header)
      std::memcpy(header + total, buffer.data(), std::min<std::uint64_t>(sizeof header - total, n));
    total += static_cast<std::uint64_t>(n);
  }
  int error = Z_OK;
  gzerror(file, &error);
  gzclose(file);
  if (n < 0 || (error != Z_OK && error != Z_STREAM_END))
    throw ImageIoError(reportedPath, "the compressed stream was not written completely (disk full or file size "
                                     "limit?)");
  std::int32_t headerSize = 0;
  std::memcpy(&headerSize, header, 4);
  double voxOffset = -1.0;
  if (headerSize == 348 && total >= 348) {
    float offset = 0.f;
    std::memcpy(&offset, header + 108, 4);
    voxOffset = offset;
  } else if (headerSize == 540 && total >= 540) {
    std::int64_t offset = 0;
    std::memcpy(&offset, header + 168, 8);
    voxOffset = static_cast<double>(offset);
  }
  if (voxOffset < 0.0)
    throw ImageIoError(reportedPath, "the NIfTI header was not written completely (disk full or file size limit?)");
  const std::uint64_t expected = static_cast<std::uint64_t>(voxOffset) + dataBytes;
  if (total < expected)
    throw ImageIoError(reportedPath, "the NIfTI writer wrote only " + std::to_string(total) + " of " +
                                         std::to_string(expected) + " bytes (disk full or file size limit?)");
}

/// The values of the image at `path` as read back by `read`, which must
/// equal `components` bit for bit.
void checkReadsBack(const std::string& path, const std::string& reportedPath, const std::vector<float>& components,
                    const std::function<std::vector<float>()>& read) {
  std::vector<float> back;
  try {
    back = read();
  } catch (const ImageIoError& e) {
    std::string problem = e.what();
    if (problem.rfind(path + ": ", 0) == 0) problem.erase(0, path.size() + 2);
    throw ImageIoError(reportedPath, "the written file does not read back (disk full or file size limit?): " +
                                         problem);
  }
  if (back.size() != components.size() ||
      std::memcmp(back.data(), components.data(), components.size() * sizeof(float)) != 0)
    throw ImageIoError(reportedPath, "the written file reads back different values");
}

std::vector<float> readNrrdFloats(const std::string& path) {
  OpenedImage image = openImageForReading(path);
  if (image.io->GetComponentType() != itk::IOComponentEnum::FLOAT)
    throw ImageIoError(path, "the data type is not float32");
  return readAllComponents(image, path);
}

}  // namespace

void checkWrittenImage(const std::string& path, const std::string& reportedPath,
                       const std::vector<float>& components) {
  const std::string lower = lowerCase(path);
  if (endsWith(lower, ".nii") || endsWith(lower, ".nii.gz"))
    checkNiftiSize(path, reportedPath, components.size() * sizeof(float));
  else if (endsWith(lower, ".nrrd") || endsWith(lower, ".nhdr"))
    checkReadsBack(path, reportedPath, components, [&] { return readNrrdFloats(path); });
  else if (isMrtrixImagePath(path))
    checkReadsBack(path, reportedPath, components, [&] { return readMrtrixImage(path).values; });
}

}  // namespace stvd::imaging::detail
