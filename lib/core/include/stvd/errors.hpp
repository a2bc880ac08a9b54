// Every error stvd reports about what it was given - options, input data,
// files - in one hierarchy: each derives from stvd::Error, which says what
// kind of problem it is, and from the standard exception that C++ and
// Python callers have always caught it as (std::invalid_argument for a bad
// choice or bad input data, std::runtime_error for a file). what() is one
// line; for a file it starts with the file's name.
//
// Front ends answer each kind one way: the `stvd` tool with one exit code
// per kind (tools/stvd_main.cpp), the Python package with ValueError for all
// but a shortfall of memory. Preconditions of the algorithms themselves
// (a source outside the domain, k out of range) stay std::invalid_argument
// with a message naming the value: a caller's mistake, not a user's.
#pragma once

#include <stdexcept>
#include <string>

namespace stvd {

/// What an Error says is wrong.
enum class ErrorKind {
  Option,            ///< a choice of options or files that makes no sense
  Input,             ///< an input that cannot be read or used as given
  NothingToCompute,  ///< the input is fine, but there is nothing to compute from it
  Output,            ///< an output that cannot be written
};

/// The base of every error below. Catch it to handle them all; kind() tells
/// them apart, what() is the one-line message.
class Error {
 public:
  virtual ~Error() = default;
  virtual ErrorKind kind() const noexcept = 0;
  virtual const char* what() const noexcept = 0;
};

namespace detail {
/// An Error of kind `Kind` that is also a `Standard` exception.
template <class Standard, ErrorKind Kind>
class ErrorOf : public Standard, public Error {
 public:
  using Standard::Standard;
  ErrorKind kind() const noexcept override { return Kind; }
  const char* what() const noexcept override { return Standard::what(); }
};
}  // namespace detail

/// A choice of options that makes no sense: a method name that does not
/// exist, k out of range, --k with Dijkstra (tool: exit code 2).
class OptionError : public ::stvd::detail::ErrorOf<std::invalid_argument, ErrorKind::Option> {
 public:
  using ErrorOf::ErrorOf;
};

/// An input that cannot be used as given: a mesh whose cells do not fit
/// together, tensors that look read in the wrong layout (tool: exit code 3).
class InputError : public ::stvd::detail::ErrorOf<std::invalid_argument, ErrorKind::Input> {
 public:
  using ErrorOf::ErrorOf;
};

/// Nothing to compute: an empty domain, a seed or target outside the image
/// or the domain, no label voxel inside the domain (tool: exit code 4).
class NothingToCompute : public ::stvd::detail::ErrorOf<std::invalid_argument, ErrorKind::NothingToCompute> {
 public:
  using ErrorOf::ErrorOf;
};

/// Input that is not an orientable 2-manifold polygon surface (an index out
/// of range, a face with fewer than 3 or repeated vertices, an edge shared
/// by more than two faces, a vertex whose faces form several fans, a
/// non-orientable surface), thrown by SurfaceDomain. what() names the face,
/// edge or vertex.
class SurfaceError : public InputError {
 public:
  using InputError::InputError;
};

namespace files {

/// An output that cannot be written. what() is one line: "<path>: <problem>".
class OutputError : public ::stvd::detail::ErrorOf<std::runtime_error, ErrorKind::Output> {
 public:
  OutputError(const std::string& path, const std::string& problem) : ErrorOf(path + ": " + problem), path_(path) {}
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

/// An output that is one of the inputs, or another output
/// (checkOutputsAreNotInputs). what() is one line: "<output path>: the
/// <output role> is the <other role> (...)".
class FileConflict : public ::stvd::detail::ErrorOf<std::runtime_error, ErrorKind::Option> {
 public:
  using ErrorOf::ErrorOf;
};

/// An input that cannot be read as a regular file: missing, a FIFO, a
/// device, a folder, or larger than its reader takes (system/files/
/// regular_file.hpp). what() is one line: "<path>: <problem>"; problem() is
/// the part after the path. The readers of the adapters report it as their
/// own error naming the file (ImageIoError, MeshFileError, TetMeshError).
class InputFileError : public ::stvd::detail::ErrorOf<std::runtime_error, ErrorKind::Input> {
 public:
  InputFileError(const std::string& path, const std::string& problem)
      : ErrorOf(path + ": " + problem), problem_(problem) {}
  const std::string& problem() const { return problem_; }

 private:
  std::string problem_;
};

}  // namespace files

namespace imaging {

/// An image, tensor or streamline file that cannot be read or written as
/// asked (the imaging adapter and the ITK file I/O). what() is one line
/// that starts with the file name: "<path>: <problem>". Its kind is Input:
/// a front end that writes turns a failed output into its own answer.
class ImageIoError : public ::stvd::detail::ErrorOf<std::runtime_error, ErrorKind::Input> {
 public:
  ImageIoError(const std::string& path, const std::string& problem) : ErrorOf(path + ": " + problem), path_(path) {}
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace imaging

namespace surface_io {

/// A surface mesh file that cannot be read or written (stvd::surface_io).
/// what() is one line naming the file (and the line or element, where
/// there is one) and the problem.
class MeshFileError : public ::stvd::detail::ErrorOf<std::runtime_error, ErrorKind::Input> {
 public:
  using ErrorOf::ErrorOf;
};

}  // namespace surface_io

namespace tetmesh {

/// A TetGen mesh file that cannot be read or used (stvd::tetmesh). what()
/// is one line naming the file (and the line, where there is one) and the
/// problem.
class TetMeshError : public ::stvd::detail::ErrorOf<std::runtime_error, ErrorKind::Input> {
 public:
  using ErrorOf::ErrorOf;
};

}  // namespace tetmesh

}  // namespace stvd
