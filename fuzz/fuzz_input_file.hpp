// What every fuzz target shares: the fuzzer's bytes as a file on disk (our
// readers, and ITK's, take paths), and the rule that a reader may only fail
// with its documented exception. Anything else escaping a reader (a
// std::bad_alloc, a std::length_error, a crash, a hang) is a finding.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace stvd::fuzz {

/// A scratch folder of this process (in /dev/shm when there is one),
/// created on first use and emptied by each FuzzInputFile.
inline const std::string& scratchFolder() {
  static const std::string folder = [] {
    const char* base = access("/dev/shm", W_OK) == 0 ? "/dev/shm" : "/tmp";
    std::string pattern = std::string(base) + "/stvd-fuzz-XXXXXX";
    if (!mkdtemp(pattern.data())) std::abort();
    return pattern;
  }();
  return folder;
}

/// Writes bytes to `scratchFolder()/name` and removes the file again on
/// destruction.
class FuzzInputFile {
 public:
  FuzzInputFile(const std::string& name, const std::uint8_t* data, std::size_t size)
      : path_(scratchFolder() + "/" + name) {
    std::FILE* f = std::fopen(path_.c_str(), "wb");
    if (!f) std::abort();
    if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
    if (std::fclose(f) != 0) std::abort();
  }
  FuzzInputFile(const std::string& name, const std::string& text)
      : FuzzInputFile(name, reinterpret_cast<const std::uint8_t*>(text.data()), text.size()) {}
  ~FuzzInputFile() { std::remove(path_.c_str()); }
  FuzzInputFile(const FuzzInputFile&) = delete;
  FuzzInputFile& operator=(const FuzzInputFile&) = delete;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace stvd::fuzz

/// Defines the libFuzzer entry point of a target that reads one file:
/// `Call` runs the reader on a path and `Expected` is the exception type
/// the reader documents for bad files.
///
///   STVD_FUZZ_READER("mesh.off", stvd::surface_io::MeshFileError,
///                    [](const std::string& p) { stvd::surface_io::readOff(p); })
#define STVD_FUZZ_READER(fileName, Expected, call)                                  \
  extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) { \
    const stvd::fuzz::FuzzInputFile input(fileName, data, size);                     \
    try {                                                                            \
      (call)(input.path());                                                          \
    } catch (const Expected&) {                                                      \
    }                                                                                \
    return 0;                                                                        \
  }
