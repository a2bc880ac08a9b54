#include "stvd/imaging/image_files.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "stvd/errors.hpp"
#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/system/files/file_identity.hpp"
#include "stvd/system/files/regular_file.hpp"

namespace fs = std::filesystem;

namespace stvd::imaging {
namespace {

std::string lowerCase(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

std::string trimmed(const std::string& s) {
  const std::size_t first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

/// A name pattern of a NRRD "data file" field, "<prefix>%<width>d<suffix>"
/// (also %i, %u, a zero flag, "%%" for a percent sign), split at its one
/// number; false for anything else, which is then taken as a plain name.
struct NamePattern {
  std::string prefix, suffix;
  bool zeroPadded = false;
  int width = 0;
  bool parse(const std::string& text) {
    bool found = false;
    std::string* part = &prefix;
    for (std::size_t i = 0; i < text.size(); ++i) {
      if (text[i] != '%') {
        *part += text[i];
        continue;
      }
      if (i + 1 < text.size() && text[i + 1] == '%') {
        *part += '%';
        ++i;
        continue;
      }
      if (found) return false;
      std::size_t j = i + 1;
      zeroPadded = j < text.size() && text[j] == '0';
      while (j < text.size() && std::isdigit(static_cast<unsigned char>(text[j])) && width < 1000)
        width = 10 * width + (text[j++] - '0');
      if (j >= text.size() || (text[j] != 'd' && text[j] != 'i' && text[j] != 'u')) return false;
      found = true;
      part = &suffix;
      i = j;
    }
    return found;
  }
  std::string name(long n) const {
    std::string digits = std::to_string(n);
    if (static_cast<int>(digits.size()) < width) digits.insert(0, width - digits.size(), zeroPadded ? '0' : ' ');
    return prefix + digits + suffix;
  }
};

/// The data files a NRRD header names in its "data file" (or "datafile")
/// field, as written there: one name, the names after "LIST", or the names
/// a "<pattern> <min> <max> <step>" field generates.
std::vector<std::string> nrrdDataFileNames(const std::string& path) {
  // Headers are text up to the first empty line; no header needs a
  // megabyte, and no more is read (the file is not checked yet).
  constexpr std::size_t kMaxHeaderBytes = 1 << 20;
  constexpr long kMaxGeneratedNames = 100000;
  std::string head;
  try {  // a FIFO or a device named like a header is not read (it would block or never end)
    head = files::readRegularFile(path, kMaxHeaderBytes, /*truncate=*/true);
  } catch (const files::InputFileError&) {
    return {};
  }
  std::istringstream in(head);
  std::string line;
  if (!std::getline(in, line) || line.rfind("NRRD000", 0) != 0) return {};
  std::vector<std::string> names;
  bool listFollows = false;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty()) break;
    if (listFollows) {
      names.push_back(trimmed(line));
      continue;
    }
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos || line[0] == '#') continue;
    const std::string field = lowerCase(trimmed(line.substr(0, colon)));
    if (field != "data file" && field != "datafile") continue;
    const std::string value = trimmed(line.substr(colon + 1));
    std::istringstream words(value);
    std::string first;
    words >> first;
    NamePattern pattern;
    long min = 0, max = 0, step = 0;
    if (first == "LIST") {
      listFollows = true;
    } else if (pattern.parse(first) && (words >> min >> max >> step) && step != 0) {
      const double steps = (static_cast<double>(max) - static_cast<double>(min)) / static_cast<double>(step);
      if (steps >= 0 && steps < kMaxGeneratedNames) {
        // The count, taken in doubles, can be one too many near the ends of
        // the range of long; no number beyond `max` or beyond that range is
        // named.
        long n = min;
        for (long k = 0; k <= static_cast<long>(steps); ++k) {
          if (step > 0 ? n > max : n < max) break;
          names.push_back(pattern.name(n));
          if (__builtin_add_overflow(n, step, &n)) break;
        }
      }
    } else {
      names.push_back(value);
    }
  }
  return names;
}

}  // namespace

std::vector<std::string> imageFilesRead(const std::string& path) {
  std::vector<std::string> files{path};
  const std::string lower = lowerCase(path);
  const fs::path folder = fs::path(path).parent_path();
  if (endsWith(lower, ".nhdr") || endsWith(lower, ".nrrd")) {
    for (const std::string& name : nrrdDataFileNames(path))
      files.push_back(fs::path(name).is_absolute() ? name : (folder / name).string());
  } else if (endsWith(lower, ".hdr")) {
    const std::string base = path.substr(0, path.size() - 4);
    files.push_back(base + ".img");
    files.push_back(base + ".img.gz");
  } else if (endsWith(lower, ".img") || endsWith(lower, ".img.gz")) {
    files.push_back(path.substr(0, path.size() - (endsWith(lower, ".gz") ? 7 : 4)) + ".hdr");
  } else if (endsWith(lower, ".mih")) {
    const std::string data = mrtrixDataFile(path);
    if (!data.empty() && data != path) files.push_back(data);
  }
  return files;
}

std::vector<std::string> imageFilesWritten(const std::string& path) {
  std::vector<std::string> files{path};
  // ITK's NRRD writer names the data file of "<base>.nhdr" "<base>.raw",
  // with ".gz" for compressed data (stvd always compresses).
  if (endsWith(lowerCase(path), ".nhdr")) files.push_back(path.substr(0, path.size() - 5) + ".raw.gz");
  return files;
}

void checkImageOutputCompanions(const std::string& path) {
  const std::vector<std::string> written = imageFilesWritten(path);
  std::error_code ec;
  const bool headerExists = fs::exists(path, ec);
  for (std::size_t c = 1; c < written.size(); ++c) {
    if (!fs::exists(written[c], ec)) continue;
    bool ownedByTheHeader = false;
    if (headerExists)
      for (const std::string& data : imageFilesRead(path))
        ownedByTheHeader = ownedByTheHeader || (data != path && files::sameFile(data, written[c]));
    if (!ownedByTheHeader)
      throw ImageIoError(path, "writing it would replace " + written[c] +
                                   ", which is not the data file of " +
                                   (headerExists ? "the header now at this path" : "an image at this path") +
                                   "; move that file or choose another output name");
  }
}

}  // namespace stvd::imaging
