// The errors of the checks that stvd's front ends (the command-line tool and
// the Python package) share. Each kind is one answer the tool gives with its
// own exit code and the Python package with ValueError; what() is the
// one-line message both show.
#pragma once

#include <stdexcept>
#include <string>

namespace stvd {

/// A choice of options that makes no sense: a method name that does not
/// exist, k out of range, --k with Dijkstra (tool: exit code 2).
class OptionError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// An input that cannot be used as given: a mesh whose cells do not fit
/// together, tensors that look read in the wrong layout (tool: exit code 3).
class InputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Nothing to compute: an empty domain, a seed or target outside the image
/// or the domain, no label voxel inside the domain (tool: exit code 4).
class NothingToCompute : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace stvd
