// Small inputs for every command of `stvd`, written by hand into a scratch
// folder, and snapshots of folders to prove that a failed run changed
// nothing. Shared by the specifications of what the tool does with its
// outputs: identity of inputs and outputs, failures while writing,
// interruption and determinism.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace stvd::testing {

/// Every file of a folder (names relative to it, recursively, hidden ones
/// included) with its bytes.
using FolderSnapshot = std::map<std::string, std::string>;
FolderSnapshot snapshot(const std::string& folder);

/// A scratch folder with "in/" holding an input of each kind and an empty
/// "out/":
///   in/t.nii        a 11 x 9 x 7 metric tensor volume (NIfTI 5D, constant
///                   anisotropic metric: use --tensor-kind metric)
///   in/t.mif        the same tensors as MRtrix stores them (order mrtrix,
///                   scanner frame; use --tensor-kind metric)
///   in/t.mih, in/t.dat   the same, header and data in two files
///   in/mask.nii     the whole grid
///   in/labels.nii   two regions: label 1 around voxel (2, 2, 2), label 2
///                   around (8, 6, 4)
///   in/cube.node, in/cube.ele   a 4 x 4 x 4 lattice of Kuhn tetrahedra
///   in/square.ply   a 3 x 3 grid of unit squares (16 vertices, ASCII PLY)
///   in/box.off      a closed unit cube of six quadrilaterals
///   in/tetra.stl    a tetrahedron as ASCII STL (12 corners, 4 vertices)
class SmallInputsTest : public ScratchFolderTest {
 protected:
  void SetUp() override;
  std::string in(const std::string& name) const { return path("in/" + name); }
  std::string out(const std::string& name) const { return path("out/" + name); }

  /// Arguments of a successful run of each command writing `output` (and,
  /// for distance, the statistics file `stats` when not empty).
  std::vector<std::string> distanceRun(const std::string& output, const std::string& stats = "") const;
  std::vector<std::string> pathRun(const std::string& output, const std::string& table) const;
  std::vector<std::string> connectivityRun(const std::string& output) const;
  std::vector<std::string> tetMeshRun(const std::string& output) const;
  std::vector<std::string> surfaceRun(const std::string& output) const;
  std::vector<std::string> tetrahedralizeRun(const std::string& base) const;

  /// Whether this build has the optional parts.
  static bool withTetrahedralize();
  static bool withVdb();
  /// Whether the tool can draw --report pages: the Python package is built
  /// (sanitizer builds leave it out).
  static bool withReports();

 private:
  /// in/t.mif, in/t.mih and in/t.dat from in/t.nii.
  void writeMrtrixTensors() const;
};

}  // namespace stvd::testing
