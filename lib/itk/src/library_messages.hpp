// ITK, the niftilib and NrrdIO inside it, and VNL print their own messages:
// ITK through its output window (a three-line "WARNING: In .../
// itkNiftiImageIO.cxx, line 1015 ..."), niftilib and NrrdIO with
// fprintf(stderr), VNL on std::cerr (a matrix dump before abort()). stvd
// promises one line of its own per problem, so every call into these
// libraries runs inside a LibraryMessageCapture, which collects that output
// instead of letting it reach the terminal.
//
// The capture diverts the process's standard error (file descriptor 2 and
// std::cerr) while it lives: output of other threads during a read or write
// of an image is collected too and not shown. Captures nest; they are
// serialised by a process-wide lock.
#pragma once

#include <memory>
#include <string>

namespace stvd::imaging::detail {

class LibraryMessageCapture {
 public:
  LibraryMessageCapture();
  ~LibraryMessageCapture();
  LibraryMessageCapture(const LibraryMessageCapture&) = delete;
  LibraryMessageCapture& operator=(const LibraryMessageCapture&) = delete;

  /// What the libraries printed since this capture began, as one line
  /// (line breaks and runs of blanks made single spaces).
  std::string text();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace stvd::imaging::detail
