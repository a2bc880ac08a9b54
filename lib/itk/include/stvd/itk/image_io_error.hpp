// The one exception type of the imaging adapter.
#pragma once

#include <stdexcept>
#include <string>

namespace stvd::imaging {

/// A file that cannot be read or written as asked. what() is one line that
/// starts with the file name: "<path>: <problem>".
class ImageIoError : public std::runtime_error {
 public:
  ImageIoError(const std::string& path, const std::string& problem)
      : std::runtime_error(path + ": " + problem), path_(path) {}
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace stvd::imaging
