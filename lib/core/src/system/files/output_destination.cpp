#include "stvd/system/files/output_destination.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <optional>

#include "stvd/system/files/output_transaction.hpp"
#include "stvd/system/files/regular_file.hpp"

namespace fs = std::filesystem;

namespace stvd::files {
namespace {

bool allDigits(const std::string& s) {
  if (s.empty() || s.size() > 9) return false;
  for (char c : s)
    if (c < '0' || c > '9') return false;
  return true;
}

/// The canonical folder of this process's descriptors: /proc/<pid>/fd, or
/// /proc/<pid>/task/<tid>/fd (/proc/thread-self/fd).
bool isOwnDescriptorFolder(const std::string& folder) {
  const std::string own = "/proc/" + std::to_string(::getpid());
  if (folder == own + "/fd") return true;
  const std::string task = own + "/task/";
  if (folder.rfind(task, 0) != 0 || folder.size() < task.size() + 4) return false;
  const std::string rest = folder.substr(task.size());
  const std::size_t slash = rest.find('/');
  return slash != std::string::npos && allDigits(rest.substr(0, slash)) && rest.substr(slash) == "/fd";
}

/// When `path` (or a chain of symbolic links from it) names one of this
/// process's descriptors (/dev/stdout -> /proc/self/fd/1, /dev/fd/3, ...),
/// its number. The links are followed one at a time, so that the last one,
/// /proc/<pid>/fd/N, is recognised before the kernel's own link behind it
/// (to "pipe:[...]" or a terminal) would be.
std::optional<int> descriptorNamed(const std::string& path) {
  std::string current = path;
  for (int hop = 0; hop < 40; ++hop) {
    const fs::path p(current);
    const std::string name = p.filename().string();
    if (name.empty() || name == "." || name == "..") return std::nullopt;
    const std::string parent = p.parent_path().empty() ? std::string(".") : p.parent_path().string();
    char* resolved = ::realpath(parent.c_str(), nullptr);
    if (!resolved) return std::nullopt;
    const std::string folder = resolved;
    std::free(resolved);
    if (isOwnDescriptorFolder(folder) && allDigits(name)) return std::stoi(name);
    const std::string full = (folder == "/" ? std::string() : folder) + "/" + name;
    struct stat status {};
    if (::lstat(full.c_str(), &status) != 0 || !S_ISLNK(status.st_mode)) return std::nullopt;
    char target[PATH_MAX];
    const ssize_t n = ::readlink(full.c_str(), target, sizeof target - 1);
    if (n <= 0) return std::nullopt;
    target[n] = '\0';
    current = target[0] == '/' ? std::string(target) : folder + "/" + target;
  }
  return std::nullopt;
}

}  // namespace

OutputDestination outputDestination(const std::string& path) {
  OutputDestination d;
  if (path.empty()) return d;
  if (const std::optional<int> fd = descriptorNamed(path)) {
    const int flags = ::fcntl(*fd, F_GETFL);
    if (flags < 0) throw OutputError(path, "names descriptor " + std::to_string(*fd) + ", which is not open");
    if ((flags & O_ACCMODE) == O_RDONLY)
      throw OutputError(path, "names descriptor " + std::to_string(*fd) + ", which is not open for writing");
    d.kind = OutputDestination::Kind::Stream;
    d.descriptor = *fd;
    d.description = *fd == 1 ? "standard output" : *fd == 2 ? "standard error" : "descriptor " + std::to_string(*fd);
    return d;
  }
  struct stat status {};
  if (::stat(path.c_str(), &status) != 0) return d;  // a new file (or a path checkOutputPath refuses)
  if (S_ISREG(status.st_mode) || S_ISDIR(status.st_mode)) return d;
  if (S_ISCHR(status.st_mode) || S_ISFIFO(status.st_mode)) {
    d.kind = OutputDestination::Kind::Stream;
    d.description = fileKindName(status.st_mode);
    return d;
  }
  throw OutputError(path, "is " + fileKindName(status.st_mode) +
                              "; stvd writes regular files, and streams to character devices (such as "
                              "/dev/null) and FIFOs, nothing else");
}

bool isStreamOutput(const std::string& path) {
  try {
    return outputDestination(path).isStream();
  } catch (const std::runtime_error&) {
    return false;
  }
}

}  // namespace stvd::files
