#include "stvd/system/files/regular_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace stvd::files {

std::string fileKindName(mode_t mode) {
  if (S_ISREG(mode)) return "a regular file";
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  if (S_ISLNK(mode)) return "a symbolic link";
  return "not a regular file";
}

RegularFile::RegularFile(const std::string& path) {
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a
  // writer; O_NOCTTY: a terminal never becomes ours.
  int fd;
  do {
    fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_NOCTTY | O_CLOEXEC);
  } while (fd < 0 && errno == EINTR);
  if (fd < 0) {
    if (errno == ENOENT) throw InputFileError(path, "no such file");
    throw InputFileError(path, std::string("cannot open: ") + std::strerror(errno));
  }
  struct stat status {};
  if (::fstat(fd, &status) != 0) {
    const int error = errno;
    ::close(fd);
    throw InputFileError(path, std::string("cannot read its status: ") + std::strerror(error));
  }
  if (!S_ISREG(status.st_mode)) {
    ::close(fd);
    throw InputFileError(path, "is " + fileKindName(status.st_mode) + ", not a regular file");
  }
  const int flags = ::fcntl(fd, F_GETFL);
  if (flags >= 0) (void)::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  fd_ = fd;
  size_ = static_cast<std::uint64_t>(status.st_size);
}

RegularFile::~RegularFile() {
  if (fd_ >= 0) ::close(fd_);
}

int RegularFile::release() {
  const int fd = fd_;
  fd_ = -1;
  return fd;
}

bool isReadableRegularFile(const std::string& path) {
  try {
    const RegularFile file(path);
    return true;
  } catch (const InputFileError&) {
    return false;
  }
}

std::string readRegularFile(const std::string& path, std::uint64_t maxBytes, bool truncate) {
  const RegularFile file(path);
  if (file.size() > maxBytes && !truncate)
    throw InputFileError(path, "is larger than " + std::to_string(maxBytes) + " bytes (" +
                                   std::to_string(file.size()) + "), more than stvd reads from such a file");
  std::string content;
  content.reserve(static_cast<std::size_t>(std::min(file.size(), maxBytes)));
  char buffer[1 << 16];
  while (content.size() < maxBytes) {
    const std::uint64_t want = std::min<std::uint64_t>(sizeof buffer, maxBytes - content.size());
    const ssize_t n = ::read(file.descriptor(), buffer, static_cast<std::size_t>(want));
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw InputFileError(path, std::string("cannot read: ") + std::strerror(errno));
    if (n == 0) return content;
    content.append(buffer, static_cast<std::size_t>(n));
  }
  if (!truncate) {  // the file grew beyond the bound after it was opened
    char probe;
    ssize_t n;
    do {
      n = ::read(file.descriptor(), &probe, 1);
    } while (n < 0 && errno == EINTR);
    if (n > 0)
      throw InputFileError(path, "is larger than " + std::to_string(maxBytes) +
                                     " bytes, more than stvd reads from such a file");
  }
  return content;
}

}  // namespace stvd::files
