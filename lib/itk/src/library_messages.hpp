// Every call into ITK runs inside a LibraryMessageCapture, which marks the
// calling thread as inside one of stvd's calls: if the process's owner
// installed stvd's output window (installItkMessageFilter,
// stvd/itk/itk_messages.hpp), ITK's messages given on this thread meanwhile
// are collected here instead of reaching the terminal. Nothing process-wide
// changes: no output window is exchanged per call, file descriptor 2 and
// std::cerr are never touched. Captures nest; captures on different threads
// are independent.
#pragma once

#include <cstddef>
#include <string>

namespace stvd::imaging::detail {

class LibraryMessageCapture {
 public:
  LibraryMessageCapture();
  ~LibraryMessageCapture();
  LibraryMessageCapture(const LibraryMessageCapture&) = delete;
  LibraryMessageCapture& operator=(const LibraryMessageCapture&) = delete;

  /// What stvd's output window was given on this thread since this capture
  /// began, as one line (line breaks and runs of blanks made single spaces);
  /// empty when the window is not installed.
  std::string text() const;

 private:
  std::size_t start_ = 0;
};

}  // namespace stvd::imaging::detail
