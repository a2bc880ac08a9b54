// Neighbourhood stencils of an implicit voxel grid: the set of integer index
// offsets that connect a voxel to its neighbours.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace stvd {

/// A symmetric set of non-zero integer offsets (di, dj, dk). Symmetric means
/// that with every offset o the set also holds -o, so the graph is undirected
/// (an asymmetric norm still measures each direction on its own).
class Stencil {
 public:
  using Offset = std::array<int, 3>;

  /// Face neighbours (6).
  static Stencil faces6();
  /// Face and edge neighbours (18).
  static Stencil faces18();
  /// The whole 3x3x3 block (26).
  static Stencil full26();
  /// Every primitive offset (gcd of |di|,|dj|,|dk| equal to 1) with all
  /// components in [-radius, radius]. radius 1 gives the 26-neighbourhood,
  /// radius 2 the 98 primitive offsets of the 5x5x5 block, radius 3 the 290
  /// of the 7x7x7 block. Non-primitive offsets are left out because they
  /// only repeat a shorter edge in the same direction.
  static Stencil primitive(int radius);
  /// "6", "18", "26", "98" (5x5x5 primitive) or "290" (7x7x7 primitive).
  /// Throws std::invalid_argument naming the accepted values otherwise.
  static Stencil byName(const std::string& name);
  /// Any symmetric set of distinct non-zero offsets; throws
  /// std::invalid_argument when the set is empty, holds (0,0,0), repeats an
  /// offset or lacks the opposite of one of its offsets.
  static Stencil fromOffsets(std::vector<Offset> offsets);

  const std::vector<Offset>& offsets() const { return offsets_; }
  int size() const { return static_cast<int>(offsets_.size()); }
  /// Largest |component| over all offsets: how far a voxel must be from the
  /// image border for all its neighbours to exist.
  int radius() const { return radius_; }

 private:
  explicit Stencil(std::vector<Offset> offsets);
  std::vector<Offset> offsets_;
  int radius_ = 0;
};

}  // namespace stvd
