// Damaged and hostile image files, as a fuzzer or a careless pipeline
// makes them: each is refused with one line naming the file (exit 3), in
// seconds and without large allocations, whatever role the image has; and
// the same data mean the same in every format. See docs/reliability.md.
#include <gtest/gtest.h>

#include <zlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "known_field.hpp"
#include "stvd/errors.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

namespace fs = std::filesystem;

constexpr int kInput = 3;

std::string slurpBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

template <class T>
void patch(std::string& bytes, std::size_t offset, T value) {
  std::memcpy(bytes.data() + offset, &value, sizeof(T));
}

class HostileImageFiles : public ScratchFolderTest {
 protected:
  void SetUp() override {
    ScratchFolderTest::SetUp();
    writeNiftiByHand(path("tensors.nii"), field.geometry, NiftiTensorLayout::SymMatrix5D,
                     std::vector<std::array<float, 6>>(field.voxelCount(), {1, 0, 1, 0, 0, 1}));
    writeScalarNiftiByHand(path("mask.nii"), field.geometry, std::vector<float>(field.voxelCount(), 1.f));
  }

  /// Runs the tool and expects a one-line refusal naming `file` and
  /// mentioning `problem`, exit 3, and no output.
  void expectRefused(std::vector<std::string> arguments, const std::string& file, const std::string& problem) {
    arguments.insert(arguments.end(), {"-o", path("out.nii.gz"), "-q"});
    const ToolRun run = runTool(arguments);
    EXPECT_EQ(run.exitCode, kInput) << run.err;
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << "not one line: " << run.err;
    EXPECT_EQ(run.err.rfind("stvd: " + file + ": ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(problem), std::string::npos) << run.err;
    EXPECT_FALSE(fs::exists(path("out.nii.gz")));
  }

  /// A copy of the scalar mask with srow_x[1] (and the qform's origin
  /// left alone) replaced.
  std::string maskWithSformEntry(const std::string& name, float value) {
    std::string bytes = slurpBytes(path("mask.nii"));
    patch<float>(bytes, 284, value);  // srow_x[1]
    writeBytes(path(name), bytes);
    return path(name);
  }

  KnownField field;
};

// --- Geometry that makes ITK's direction-cosine SVD hang or abort ----------

TEST_F(HostileImageFiles, SformWithAHugeOrNonFiniteEntryIsRefusedForEveryRole) {
  const std::string seed = "--seed-voxel=5,4,3";
  for (const float value : {3e38f, -std::numeric_limits<float>::infinity(), std::numeric_limits<float>::quiet_NaN()}) {
    SCOPED_TRACE(value);
    const std::string bad = maskWithSformEntry("bad.nii", value);
    expectRefused({"distance", path("tensors.nii"), seed, "--mask", bad}, bad, "srow_x[1]");
    expectRefused({"distance", path("tensors.nii"), "--seeds", bad}, bad, "srow_x[1]");
    std::string tensors = slurpBytes(path("tensors.nii"));
    patch<float>(tensors, 284, value);
    writeBytes(path("bad_tensors.nii"), tensors);
    expectRefused({"distance", path("bad_tensors.nii"), seed}, path("bad_tensors.nii"), "srow_x[1]");
    expectRefused({"connectivity", path("tensors.nii"), "--labels", bad}, bad, "srow_x[1]");
  }
}

// Found by fuzzing (fuzz/regressions/tensor_volume and scalar_image): a
// NIfTI-1 header with the magic of another NIfTI version ("n+2", "ni5") is
// NIfTI to niftilib, which reads its sform; the screening took it for
// Analyze and did not check the sform, and a NaN reached VNL's abort().
TEST_F(HostileImageFiles, AnySformIsCheckedWhateverTheMagicSays) {
  for (const char* magic : {"n+2", "ni5", "xyz"}) {
    SCOPED_TRACE(magic);
    std::string bytes = slurpBytes(maskWithSformEntry("bad.nii", std::numeric_limits<float>::quiet_NaN()));
    std::memcpy(bytes.data() + 344, magic, 4);
    writeBytes(path("bad.nii"), bytes);
    expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("bad.nii")}, path("bad.nii"),
                  "srow_x[1]");
  }
}

TEST_F(HostileImageFiles, FarOriginIsRefusedUpFrontNotAnInternalErrorOfPathTracing) {
  HandGeometry far = field.geometry;
  far.originLps = {1e17, 0, 0};
  writeTensorNrrdByHand(path("far.nrrd"), far, "left-posterior-superior",
                        std::vector<SymTensor3>(field.voxelCount(), field.lpsMetric()), nullptr);
  const ToolRun run = runTool({"path", path("far.nrrd"), "--tensor-kind", "metric", "--seed-voxel", "1,1,1",
                               "--target-voxel", "9,7,5", "-o", path("paths.tck"), "-q"});
  EXPECT_EQ(run.exitCode, kInput) << run.err;
  EXPECT_EQ(run.err.rfind("stvd: " + path("far.nrrd") + ": ", 0), 0u) << run.err;
  EXPECT_NE(run.err.find("beyond the 1e+06 mm"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(path("paths.tck")));
}

// --- Sizes the file cannot hold ---------------------------------------------

/// A NRRD header of a scalar image with these sizes and the geometry of the
/// known field (so that an image of its 11 x 9 x 7 voxels is on the grid of
/// tensors.nii, and a side input gets as far as its data).
std::string nrrdHeader(const std::string& sizes, const std::string& encoding, const std::string& extra = "") {
  const HandGeometry g = KnownField().geometry;
  std::ostringstream s;
  s.precision(17);
  s << "NRRD0004\ntype: float\ndimension: 3\nsizes: " << sizes << "\nendian: little\nencoding: " << encoding
    << "\nspace: left-posterior-superior\nspace directions:";
  for (int a = 0; a < 3; ++a)
    s << " (" << g.directionLps[a] * g.spacing[a] << "," << g.directionLps[3 + a] * g.spacing[a] << ","
      << g.directionLps[6 + a] * g.spacing[a] << ")";
  s << "\nspace origin: (" << g.originLps[0] << "," << g.originLps[1] << "," << g.originLps[2] << ")\n" << extra << "\n";
  return s.str();
}

TEST_F(HostileImageFiles, NrrdSizesBeyondTheFileAreRefusedBeforeAnythingIsAllocated) {
  // 3.2 GB claimed by a file of 140 bytes: ITK used to zero-fill it all
  // (13 s) before noticing; 48 GB ended in "out of memory", exit 1.
  writeBytes(path("3gb.nrrd"), nrrdHeader("1000 1000 800", "raw") + "0123456789");
  writeBytes(path("48gb.nrrd"), nrrdHeader("4000 3000 1000", "raw") + "0123456789");
  std::string gz(64, '\0');
  writeBytes(path("gz.nrrd"), nrrdHeader("1000 1000 800", "gzip") + gz);
  // As the tensor input, each is refused for what its data would need. As a
  // side input (the mask) its grid is compared with the tensors' first,
  // from its header alone: refused before its data are even looked at.
  // All at once: little work, counted in processor time (which a loaded
  // machine does not stretch, as it does the time on the clock).
  const double start = toolProcessorSeconds();
  expectRefused({"distance", path("3gb.nrrd"), "--seed-voxel=5,4,3"}, path("3gb.nrrd"), "3200000000");
  expectRefused({"distance", path("48gb.nrrd"), "--seed-voxel=5,4,3"}, path("48gb.nrrd"), "12000000000 values");
  expectRefused({"distance", path("gz.nrrd"), "--seed-voxel=5,4,3"}, path("gz.nrrd"), "3200000000");
  for (const char* name : {"3gb.nrrd", "gz.nrrd"})
    expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path(name)}, path(name),
                  "the mask is on another grid than " + path("tensors.nii") + " (size 1000x1000x800");
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("48gb.nrrd")},
                path("48gb.nrrd"), "too many voxels");  // no grid stvd takes
  EXPECT_LT(toolProcessorSeconds() - start, 10.0);
}

TEST_F(HostileImageFiles, NiftiSizesOverflowingOrBeyondTheMachineAreRefused) {
  std::string bytes = slurpBytes(path("mask.nii"));
  patch<std::int16_t>(bytes, 40, 7);  // dim[0]: seven axes of 32767
  for (int d = 1; d <= 7; ++d) patch<std::int16_t>(bytes, 40 + 2 * d, 32767);
  writeBytes(path("overflow.nii"), bytes);
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("overflow.nii")},
                path("overflow.nii"), "overflow");
  patch<std::int16_t>(bytes, 40, 3);
  writeBytes(path("huge.nii"), bytes);
  expectRefused({"distance", path("huge.nii"), "--seed-voxel=5,4,3"}, path("huge.nii"), "of memory");
  // As a side input, from its header alone (the grid is no grid stvd takes).
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("huge.nii")}, path("huge.nii"),
                "too many voxels");
}

// --- NRRD data that crash or hang NrrdIO --------------------------------------

TEST_F(HostileImageFiles, AsciiNrrdWithALongTokenOrNulBytesIsRefused) {
  // NrrdIO reads ascii tokens with an unbounded %s into a stack buffer of
  // about 1 KB: "stack smashing detected", SIGABRT; NUL bytes gave SIGSEGV.
  writeBytes(path("long.nrrd"), nrrdHeader("11 9 7", "ascii") + std::string(2000, '1') + " 1\n");
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("long.nrrd")},
                path("long.nrrd"), "longer than 64 characters");
  std::string nul = nrrdHeader("11 9 7", "ascii") + "1 2 ";
  nul += std::string(3, '\0') + " 3\n";
  writeBytes(path("nul.nrrd"), nul);
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("nul.nrrd")},
                path("nul.nrrd"), "NUL byte");
  writeBytes(path("short.nrrd"), nrrdHeader("11 9 7", "ascii") + "1 2 3\n");
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("short.nrrd")},
                path("short.nrrd"), "hold 3 values where the header needs 693");
}

TEST_F(HostileImageFiles, NrrdFieldsThatNrrdIoCannotParseSafelyAreRefusedBeforeItSeesThem) {
  // NrrdIO quotes a value it cannot parse in an error message of about 1 KB
  // on the stack: a field line of 1,000 bytes ended in "buffer overflow
  // detected", SIGABRT. A second "type" hid a long first one from the screen
  // (it kept the last; NrrdIO parses the first), and unknown fields were let
  // through to NrrdIO, which quotes them too.
  const std::string longValue(2000, '1');
  const auto refusedAsMask = [&](const std::string& name, const std::string& bytes, const std::string& problem) {
    writeBytes(path(name), bytes);
    expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path(name)}, path(name), problem);
  };
  refusedAsMask("long-labels.nrrd", nrrdHeader("11 9 7", "raw", "labels: \"" + longValue + "\"\n"),
                "the NRRD field \"labels\" is longer than 512 bytes");
  refusedAsMask("long-first-type.nrrd",
                "NRRD0004\ntype: fl" + longValue + "\n" + nrrdHeader("11 9 7", "raw").substr(9),
                "the NRRD field \"type\" is longer than 512 bytes");
  refusedAsMask("two-types.nrrd", "NRRD0004\ntype: flaot\n" + nrrdHeader("11 9 7", "raw").substr(9),
                "the NRRD field \"type\" is given twice");
  refusedAsMask("unknown.nrrd", nrrdHeader("11 9 7", "raw", longValue + ": 1\n"), "is not a NRRD field");
  refusedAsMask("spelled-twice.nrrd", nrrdHeader("11 9 7", "raw", "lineskip: 0\nline skip: 0\n"),
                "the NRRD field \"line skip\" is given twice");
  // What real headers hold stays readable: long content and comments, key/value
  // pairs, NrrdIO's other spellings of a field.
  const std::string fine = nrrdHeader("11 9 7", "raw", "content: " + longValue + "\n#" + longValue + "\nkey:=" +
                                                           longValue + "\nbyteskip: 0\n") +
                           std::string(11 * 9 * 7 * 4, '\0');
  writeBytes(path("fine.nrrd"), fine);
  const ToolRun run = runTool({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("fine.nrrd"), "-o",
                               path("out.nii.gz"), "-q"});
  EXPECT_NE(run.err.find("the domain is empty"), std::string::npos) << run.err;  // an all-zero mask, read
  EXPECT_EQ(run.err.find("NRRD"), std::string::npos) << run.err;
}

TEST_F(HostileImageFiles, DataFileThatIsADeviceOrAbsurdSkipsAreRefused) {
  writeBytes(path("device.nhdr"), nrrdHeader("11 9 7", "raw", "data file: /dev/zero\nline skip: 100000000000\n"));
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("device.nhdr")},
                path("device.nhdr"), "not a regular file");
  writeBytes(path("data.raw"), std::string(11 * 9 * 7 * 4, '\0'));
  writeBytes(path("lines.nhdr"), nrrdHeader("11 9 7", "raw", "data file: data.raw\nline skip: 100000000000\n"));
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("lines.nhdr")},
                path("lines.nhdr"), "line skip");
  writeBytes(path("bytes.nhdr"), nrrdHeader("11 9 7", "raw", "data file: data.raw\nbyte skip: 100000000000\n"));
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("bytes.nhdr")},
                path("bytes.nhdr"), "byte skip");
  writeBytes(path("pattern.nhdr"), nrrdHeader("11 9 7", "raw", "data file: slice%s%n.raw 1 7 1\n"));
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("pattern.nhdr")},
                path("pattern.nhdr"), "several files");
}

// --- One line on stderr -------------------------------------------------------

TEST_F(HostileImageFiles, AnAnalyzeStyleHeaderIsOneWarningInOurWordsAndInTheStatistics) {
  // ITK prints three lines of its own ("WARNING: In .../itkNiftiImageIO.cxx,
  // line ...") for a header without NIfTI magic, also on success.
  std::string tensors = slurpBytes(path("tensors.nii"));
  std::memset(tensors.data() + 344, 0, 4);
  writeBytes(path("analyze.nii"), tensors);
  const ToolRun run = runTool({"distance", path("analyze.nii"), "--seed-voxel", "5,4,3", "--tensor-kind", "metric",
                               "--tensor-order", "lower", "-o", path("d.nii.gz"), "--stats", path("stats.json"), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_EQ(run.err, "stvd: warning: " + path("analyze.nii") +
                         ": has an Analyze 7.5 header (no NIfTI magic): the format does not define its orientation, "
                         "and the image is read with ITK's default orientation\n");
  EXPECT_NE(slurpBytes(path("stats.json")).find("\"warnings\": [\"" + path("analyze.nii") + ": has an Analyze 7.5"),
            std::string::npos);
}

// --- Same data, same meaning, in every format --------------------------------

TEST_F(HostileImageFiles, ANonFiniteTensorComponentIsNonFiniteInNiftiAsInNrrd) {
  std::vector<std::array<float, 6>> tensors(field.voxelCount(), {1, 0, 1, 0, 0, 1});
  tensors[7][2] = std::numeric_limits<float>::quiet_NaN();
  tensors[8][5] = std::numeric_limits<float>::infinity();
  writeNiftiByHand(path("nan.nii"), field.geometry, NiftiTensorLayout::SymMatrix5D, tensors);
  std::vector<SymTensor3> nrrdTensors(field.voxelCount(), SymTensor3{1, 0, 0, 1, 0, 1});
  nrrdTensors[7].xz = std::numeric_limits<float>::quiet_NaN();
  nrrdTensors[8].zz = std::numeric_limits<float>::infinity();
  writeTensorNrrdByHand(path("nan.nrrd"), field.geometry, "left-posterior-superior", nrrdTensors, nullptr);
  for (const std::string& file : {path("nan.nii"), path("nan.nrrd")}) {
    SCOPED_TRACE(file);
    const imaging::TensorVolume v = imaging::readTensorVolume(file).volume;
    for (const std::size_t voxel : {std::size_t{7}, std::size_t{8}}) {
      const SymTensor3& t = v.tensors[voxel];
      EXPECT_FALSE(std::isfinite(t.xx + t.xy + t.xz + t.yy + t.yz + t.zz)) << "voxel " << voxel;
    }
    EXPECT_EQ(v.tensors[6].xx, 1.f);
  }
}

TEST_F(HostileImageFiles, LabelsStayExactIntegers) {
  // Through float32, 16777216 and 16777217 became one label, 2147483647
  // became 2147483648, and +-1e30 were accepted.
  std::vector<float> zero(field.voxelCount(), 0.f);
  writeScalarNiftiByHand(path("int32.nii"), field.geometry, zero);
  std::string bytes = slurpBytes(path("int32.nii"));
  patch<std::int16_t>(bytes, 70, 8);  // datatype int32, same size as float32
  const std::int32_t labels[3] = {16777216, 16777217, 2147483647};
  for (int i = 0; i < 3; ++i) patch<std::int32_t>(bytes, 352 + 4 * i, labels[i]);
  writeBytes(path("int32.nii"), bytes);
  const imaging::LabelImage image = imaging::readLabelImage(path("int32.nii"));
  EXPECT_EQ(image.labels[0], 16777216);
  EXPECT_EQ(image.labels[1], 16777217);
  EXPECT_EQ(image.labels[2], 2147483647);

  for (const float bad : {2.5f, 1e30f, -1e30f, std::numeric_limits<float>::infinity()}) {
    SCOPED_TRACE(bad);
    std::vector<float> values = zero;
    values[4] = bad;
    writeScalarNiftiByHand(path("float.nii"), field.geometry, values);
    try {
      imaging::readLabelImage(path("float.nii"));
      ADD_FAILURE() << "accepted";
    } catch (const imaging::ImageIoError& e) {
      EXPECT_NE(std::string(e.what()).find("voxel (4, 0, 0) holds"), std::string::npos) << e.what();
    }
  }
}

TEST_F(HostileImageFiles, LargeLabelsAreDistinctRegionsOfConnectivity) {
  std::vector<float> zero(field.voxelCount(), 0.f);
  writeScalarNiftiByHand(path("labels.nii"), field.geometry, zero);
  std::string bytes = slurpBytes(path("labels.nii"));
  patch<std::int16_t>(bytes, 70, 8);
  patch<std::int32_t>(bytes, 352 + 4 * (1 + 11 * (1 + 9 * 1)), 16777216);
  patch<std::int32_t>(bytes, 352 + 4 * (8 + 11 * (6 + 9 * 5)), 16777217);
  writeBytes(path("labels.nii"), bytes);
  const ToolRun run = runTool({"connectivity", path("tensors.nii"), "--labels", path("labels.nii"), "-o",
                               path("table.tsv"), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  const std::string table = slurpBytes(path("table.tsv"));
  EXPECT_NE(table.find("16777216\t16777217"), std::string::npos) << table;
}

TEST_F(HostileImageFiles, AFiveDimensionalNiftiOfOneSliceIsAThinVolume) {
  HandGeometry thin = field.geometry;
  thin.size = {11, 9, 1};
  const std::size_t n = 11 * 9;
  writeNiftiByHand(path("slice.nii"), thin, NiftiTensorLayout::SymMatrix5D,
                   std::vector<std::array<float, 6>>(n, {1, 0, 1, 0, 0, 1}));
  writeTensorNrrdByHand(path("slice.nrrd"), thin, "left-posterior-superior",
                        std::vector<SymTensor3>(n, SymTensor3{1, 0, 0, 1, 0, 1}), nullptr);
  const GridGeometry nifti = imaging::readTensorVolume(path("slice.nii")).volume.geometry;
  const GridGeometry nrrd = imaging::readTensorVolume(path("slice.nrrd")).volume.geometry;
  EXPECT_EQ(nifti.size[0], 11u);
  EXPECT_EQ(nifti.size[1], 9u);
  EXPECT_EQ(nifti.size[2], 1u);
  EXPECT_EQ(imaging::geometryMismatch(nifti, nrrd), "");
  EXPECT_NEAR(nifti.spacing[2], 2.0, 1e-6);
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(nifti.origin[a], thin.originLps[a], 1e-4);
}

// --- Options settled before the computation -----------------------------------

TEST_F(HostileImageFiles, UpperCaseOutputExtensionAndUnrepresentableUnreachableValueAreUsageErrors) {
  ToolRun run = runTool({"distance", path("tensors.nii"), "--seed-voxel", "5,4,3", "-o", path("D.NII.GZ"), "-q"});
  EXPECT_EQ(run.exitCode, 2) << run.err;
  EXPECT_NE(run.err.find("lower case"), std::string::npos) << run.err;
  run = runTool({"distance", path("tensors.nii"), "--seed-voxel", "5,4,3", "-o", path("d.nii"),
                 "--unreachable-value", "1e300", "-q"});
  EXPECT_EQ(run.exitCode, 2) << run.err;
  EXPECT_NE(run.err.find("float32"), std::string::npos) << run.err;
  EXPECT_FALSE(fs::exists(path("d.nii")));
}

}  // namespace
}  // namespace stvd::testing
