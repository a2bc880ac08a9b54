#include "stvd/itk/atomic_output.hpp"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <system_error>
#include <vector>

#include "stvd/itk/image_io_error.hpp"

namespace fs = std::filesystem;

namespace stvd::imaging {
namespace {

std::string folderOf(const std::string& path) {
  const fs::path folder = fs::path(path).parent_path();
  return folder.empty() ? std::string(".") : folder.string();
}

}  // namespace

void checkOutputPath(const std::string& path) {
  if (path.empty()) throw ImageIoError("(output)", "the output path is empty");
  if (fs::path(path).filename().empty())
    throw ImageIoError(path, "the output path names a folder, not a file");
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw ImageIoError(path, "the output path is an existing folder");
  const std::string folder = folderOf(path);
  if (!fs::exists(folder, ec)) throw ImageIoError(path, "the output folder '" + folder + "' does not exist");
  if (!fs::is_directory(folder, ec)) throw ImageIoError(path, "'" + folder + "' is not a folder");
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    throw ImageIoError(path, "the output folder '" + folder + "' is not writable");
}

AtomicOutput::AtomicOutput(std::string path) : path_(std::move(path)) {
  checkOutputPath(path_);
  folder_ = folderOf(path_);
  static std::atomic<unsigned> counter{0};
  // The staging folder lives in the output folder, so that the final rename
  // never crosses a file system.
  for (int attempt = 0; attempt < 100; ++attempt) {
    const fs::path candidate = fs::path(folder_) / (".stvd-staging-" + std::to_string(::getpid()) +
                                                    "-" + std::to_string(counter++));
    std::error_code ec;
    if (fs::create_directory(candidate, ec)) {
      stagingFolder_ = candidate.string();
      stagingPath_ = (candidate / fs::path(path_).filename()).string();
      return;
    }
    if (ec) throw ImageIoError(path_, "cannot create a staging folder in '" + folder_ + "': " + ec.message());
  }
  throw ImageIoError(path_, "cannot create a staging folder in '" + folder_ + "'");
}

AtomicOutput::~AtomicOutput() {
  if (!committed_) removeStaging();
}

void AtomicOutput::commit() {
  std::error_code ec;
  if (!fs::exists(stagingPath_, ec)) throw ImageIoError(path_, "the writer produced no file");
  // Companion files (a detached header's data file) go first, so the main
  // file never points at a file that is not there yet.
  std::vector<fs::path> staged;
  for (const auto& entry : fs::directory_iterator(stagingFolder_, ec)) staged.push_back(entry.path());
  if (ec) throw ImageIoError(path_, "cannot list the staging folder: " + ec.message());
  const fs::path main = fs::path(stagingPath_);
  for (const fs::path& file : staged) {
    if (file == main) continue;
    fs::rename(file, fs::path(folder_) / file.filename(), ec);
    if (ec) throw ImageIoError(path_, "cannot move " + file.filename().string() + " into place: " + ec.message());
  }
  fs::rename(main, path_, ec);
  if (ec) throw ImageIoError(path_, "cannot move the output into place: " + ec.message());
  committed_ = true;
  removeStaging();
}

void AtomicOutput::removeStaging() noexcept {
  if (stagingFolder_.empty()) return;
  std::error_code ec;
  fs::remove_all(stagingFolder_, ec);
}

}  // namespace stvd::imaging
