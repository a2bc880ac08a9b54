#include "stvd/system/files/file_contents.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "stvd/system/files/output_transaction.hpp"

namespace stvd::files {

void writeFileContents(const std::string& path, const std::string& bytes) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd < 0) throw OutputError(path, std::string("cannot create the file: ") + std::strerror(errno));
  std::size_t written = 0;
  while (written < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + written, bytes.size() - written);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const std::string reason = n < 0 ? std::strerror(errno) : "the system wrote nothing";
      ::close(fd);
      throw OutputError(path, "wrote " + std::to_string(written) + " of " + std::to_string(bytes.size()) +
                                  " bytes: " + reason);
    }
    written += static_cast<std::size_t>(n);
  }
  if (::close(fd) != 0) throw OutputError(path, std::string("cannot close the file: ") + std::strerror(errno));
}

}  // namespace stvd::files
