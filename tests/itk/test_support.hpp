// Helpers of the imaging adapter and tool tests: scratch folders, files
// written byte by byte (independent of the readers under test), small
// matrix algebra and a runner for the real `stvd` executable.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "stvd/voxel_grid/grid_geometry.hpp"
#include "stvd/imaging/tensor_frames.hpp"
#include "stvd/types.hpp"

namespace stvd::testing {

using imaging::Matrix3;

/// The shipped DTI sample (sample_data/dti_philips_biobank).
std::string sampleFile(const std::string& name);

/// A fresh, empty folder per test, removed afterwards.
class ScratchFolderTest : public ::testing::Test {
 protected:
  void SetUp() override;
  void TearDown() override;
  std::string path(const std::string& name) const { return (folder_ / name).string(); }
  const std::filesystem::path& folder() const { return folder_; }
  /// Names of the entries of a folder, sorted (hidden ones included).
  static std::vector<std::string> listFolder(const std::filesystem::path& folder);

 private:
  std::filesystem::path folder_;
};

// --- Small linear algebra -------------------------------------------------

/// Rotation by `degrees` about the axis (x, y, z) (normalised here).
Matrix3 rotation(double x, double y, double z, double degrees);
Matrix3 transpose(const Matrix3& m);
Matrix3 multiply(const Matrix3& a, const Matrix3& b);
Matrix3 tensorMatrix(const SymTensor3& t);
SymTensor3 symmetricPart(const Matrix3& m);
/// m^T t m (the inverse change of frame of changeTensorFrame for orthogonal m).
SymTensor3 conjugateTranspose(const SymTensor3& t, const Matrix3& m);
/// Largest |a - b| over the six components, relative to the largest |b|.
double relativeDifference(const SymTensor3& a, const SymTensor3& b);

// --- Files written by hand ------------------------------------------------

/// Geometry in LPS, the way ITK reports it.
struct HandGeometry {
  std::array<int, 3> size{1, 1, 1};
  std::array<double, 3> spacing{1, 1, 1};
  std::array<double, 3> originLps{0, 0, 0};
  Matrix3 directionLps{1, 0, 0, 0, 1, 0, 0, 0, 1};  // columns = index axes
  GridGeometry grid() const;
};

/// Writes a tensor NRRD: text header plus raw little-endian float32 data,
/// component axis first. `space` is "left-posterior-superior",
/// "right-anterior-superior" or "left-anterior-superior" (geometry and
/// measurement frame are converted into it); an empty `measurementFrameLps` leaves the field out.
/// `confidence` non-empty writes kind 3D-masked-symmetric-matrix.
void writeTensorNrrdByHand(const std::string& path, const HandGeometry& g, const std::string& space,
                           const std::vector<SymTensor3>& componentsInFileFrame,
                           const Matrix3* measurementFrameLps, const std::vector<float>& confidence = {},
                           bool gzip = false);

enum class NiftiTensorLayout { SymMatrix5D, SixVolumes4D, SixVector5DNoIntent };

/// Writes a NIfTI-1 file (.nii, uncompressed) with identical qform and
/// sform (code 1, scanner) for a geometry whose direction has determinant
/// +1. `values` are written as given: for SymMatrix5D and SixVector5DNoIntent
/// six per voxel, voxel after voxel in NIfTI's 5th dimension (volume-major
/// over the 6 components), for SixVolumes4D likewise over the 4th.
void writeNiftiByHand(const std::string& path, const HandGeometry& g, NiftiTensorLayout layout,
                      const std::vector<std::array<float, 6>>& componentsPerVoxel);

/// A 3D float32 NIfTI-1 scalar image, or a 4D one with `volumes` > 1.
void writeScalarNiftiByHand(const std::string& path, const HandGeometry& g, const std::vector<float>& values,
                            int volumes = 1);

// --- The executable -----------------------------------------------------

struct ToolRun {
  int exitCode = -1;
  std::string out;
  std::string err;
};

/// The `stvd` under test: the one built with the tests, or the program the
/// environment variable STVD_TEST_EXECUTABLE names (to run the tool
/// specifications against another build, e.g. an older release).
std::string toolExecutable();

/// Runs `stvd` with these arguments (each passed as one word), capturing
/// stdout and stderr. A run ended by a signal has the exit code the shell
/// reports, 128 + the signal's number; a run still going after 600 s (a
/// hang, even on a loaded machine; STVD_TEST_TOOL_TIMEOUT sets another) is
/// ended (exit code 124).
ToolRun runTool(const std::vector<std::string>& arguments);

/// Runs a bash script in which "$0" is `stvd` and "$@" these arguments, for
/// example one that runs the tool under "ulimit -f 0; trap '' XFSZ", which
/// makes every write beyond the limit fail with EFBIG instead of ending the
/// tool. The exit code is the script's (124 after 600 s); stdout and stderr
/// are captured.
ToolRun runToolInBash(const std::string& script, const std::vector<std::string>& arguments);

/// The processor time (user and system, seconds) the tool runs of this test
/// program have used so far, with their children: how much work a run did,
/// whatever the load of the machine (wall-clock time is not).
double toolProcessorSeconds();
/// A tab-separated table with a header line (the TSV files of `stvd path`
/// and `stvd connectivity`) as rows of named columns.
std::vector<std::map<std::string, std::string>> readTsv(const std::string& path);

}  // namespace stvd::testing
