// MRtrix image files (.mif, .mif.gz, .mih) written byte by byte here, as
// MRtrix's format description says, and read by stvd's own parser: layouts
// with reversed and permuted axes, every datatype family, scaling, the
// scanner transform, tensors in MRtrix's convention, and hostile headers
// that must fail with one line before any large allocation.
#include <gtest/gtest.h>

#include <zlib.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "stvd/itk/image_io_error.hpp"
#include "stvd/itk/mrtrix_image.hpp"
#include "stvd/itk/scalar_image.hpp"
#include "stvd/itk/tensor_volume.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

using imaging::ImageIoError;

/// The header lines (without "mrtrix image", "file:" and "END"), the data
/// right after it at a 4-byte aligned offset.
std::string mifBytes(const std::string& lines, const std::string& data) {
  std::string head = "mrtrix image\n" + lines;
  std::size_t offset = head.size() + 32;
  offset = (offset + 3) / 4 * 4;
  std::string header = head + "file: . " + std::to_string(offset) + "\nEND\n";
  header.resize(offset, ' ');
  return header + data;
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

template <class T>
std::string bytesOf(const std::vector<T>& values, bool bigEndian) {
  std::string out;
  for (const T& v : values) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (bigEndian) std::reverse(b, b + sizeof(T));
    out.append(b, sizeof(T));
  }
  return out;
}

const std::string kTransform =  // RAS: i -> -x (a flipped axis, as in LAS storage), j -> +y, k -> +z
    "transform: -1,0,0,10\ntransform: 0,1,0,-20\ntransform: 0,0,1,30\n";

class MrtrixFiles : public ScratchFolderTest {};

TEST_F(MrtrixFiles, LayoutStridesPlaceEachStoredValueAtItsVoxel) {
  // 3 x 2 x 2 voxels stored with axis 0 reversed and slowest, axis 2
  // fastest: layout -2,+1,+0. Value of voxel (i,j,k) = 100 i + 10 j + k.
  std::vector<std::int16_t> stored;
  for (int i = 2; i >= 0; --i)          // rank 2, reversed
    for (int j = 0; j < 2; ++j)         // rank 1
      for (int k = 0; k < 2; ++k)       // rank 0
        stored.push_back(static_cast<std::int16_t>(100 * i + 10 * j + k));
  writeBytes(path("a.mif"), mifBytes("dim: 3,2,2\nvox: 1.5,2,2.5\nlayout: -2,+1,+0\ndatatype: Int16BE\n"
                                     "scaling: 0.5,2\n" + kTransform,
                                     bytesOf(stored, true)));
  const imaging::ScalarImage image = imaging::readScalarImage(path("a.mif"));
  ASSERT_EQ(image.values.size(), 12u);
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 3; ++i)
        EXPECT_EQ(image.values[i + 3 * (j + 2 * k)], 0.5f + 2.f * (100 * i + 10 * j + k)) << i << j << k;
  // Geometry: spacing from vox, the RAS transform turned into LPS.
  const GridGeometry& g = image.geometry;
  EXPECT_EQ(g.spacing, (std::array<double, 3>{1.5, 2.0, 2.5}));
  const Vec3d last = g.indexToPhysicalPoint(2, 1, 1);  // RAS (10 - 3, -20 + 2, 30 + 2.5)
  EXPECT_NEAR(last.x, -7.0, 1e-12);
  EXPECT_NEAR(last.y, 18.0, 1e-12);
  EXPECT_NEAR(last.z, 32.5, 1e-12);
}

TEST_F(MrtrixFiles, EveryDatatypeFamilyAndByteOrderReads) {
  const std::vector<double> expected{0, 1, -2, 3, 4, 5, 6, 7};
  const auto run = [&](const std::string& type, const std::string& data) {
    writeBytes(path("t.mif"), mifBytes("dim: 2,2,2\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: " + type + "\n", data));
    const imaging::ScalarImage image = imaging::readScalarImage(path("t.mif"));
    for (std::size_t n = 0; n < 8; ++n)
      EXPECT_EQ(image.values[n], type.rfind("UInt", 0) == 0 && n == 2 ? 0.f : float(expected[n])) << type << " " << n;
  };
  auto as = [&](auto zero, bool big) {
    std::vector<decltype(zero)> v;
    for (double x : expected) v.push_back(static_cast<decltype(zero)>(x));
    return bytesOf(v, big);
  };
  run("Float32LE", as(0.f, false));
  run("Float32BE", as(0.f, true));
  run("Float64LE", as(0.0, false));
  run("Float64BE", as(0.0, true));
  run("Int8", as(std::int8_t{}, false));
  run("Int16LE", as(std::int16_t{}, false));
  run("Int32BE", as(std::int32_t{}, true));
  run("Int64LE", as(std::int64_t{}, false));
  // Unsigned types cannot hold -2: write 0 there.
  std::vector<std::uint16_t> u16{0, 1, 0, 3, 4, 5, 6, 7};
  run("UInt16BE", bytesOf(u16, true));
  std::vector<std::uint32_t> u32{0, 1, 0, 3, 4, 5, 6, 7};
  run("UInt32LE", bytesOf(u32, false));
  std::vector<std::uint8_t> u8{0, 1, 0, 3, 4, 5, 6, 7};
  run("UInt8", bytesOf(u8, false));
}

TEST_F(MrtrixFiles, BitImagesHoldTheFirstVoxelInTheTopBit) {
  // 10 voxels: 1 0 1 1 0 0 0 1 | 1 0 -> bytes 0b10110001, 0b10000000.
  writeBytes(path("m.mif"), mifBytes("dim: 10,1,1\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: Bit\n",
                                     std::string{char(0xB1), char(0x80)}));
  const imaging::ScalarImage image = imaging::readScalarImage(path("m.mif"));
  EXPECT_EQ(image.values, (std::vector<float>{1, 0, 1, 1, 0, 0, 0, 1, 1, 0}));
}

TEST_F(MrtrixFiles, AHeaderWithADataFileAndACompressedMifRead) {
  const std::vector<float> values{1, 2, 3, 4, 5, 6, 7, 8};
  // .mih: no END line (MRtrix writes none), data in a file next to it at an offset.
  writeBytes(path("h.mih"), "mrtrix image\ndim: 2,2,2\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: Float32LE\n"
                            "file: h.dat 6\n");
  writeBytes(path("h.dat"), "xxxxxx" + bytesOf(values, false));
  EXPECT_EQ(imaging::readScalarImage(path("h.mih")).values, values);
  // .mif.gz: the whole file compressed.
  const std::string mif = mifBytes("dim: 2,2,2\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: Float32LE\n",
                                   bytesOf(values, false));
  gzFile gz = gzopen(path("c.mif.gz").c_str(), "wb");
  gzwrite(gz, mif.data(), static_cast<unsigned>(mif.size()));
  gzclose(gz);
  EXPECT_EQ(imaging::readScalarImage(path("c.mif.gz")).values, values);
}

// A compressed file is checked against its header before its data are
// kept: a few kB of zeros that expand to megabytes, under a header that
// declares gigabytes, fail without the megabytes being allocated; so does
// a stream cut short.
TEST_F(MrtrixFiles, CompressedFilesThatHoldLessThanTheirHeaderDeclaresFailWithOneLine) {
  const std::string bomb = mifBytes("dim: 1000,1000,1000\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: Float32LE\n",
                                    std::string(8 << 20, '\0'));
  gzFile gz = gzopen(path("bomb.mif.gz").c_str(), "wb9");
  gzwrite(gz, bomb.data(), static_cast<unsigned>(bomb.size()));
  gzclose(gz);
  try {
    imaging::readScalarImage(path("bomb.mif.gz"));
    ADD_FAILURE() << "accepted";
  } catch (const ImageIoError& e) {
    EXPECT_NE(std::string(e.what()).find("truncated"), std::string::npos) << e.what();
  }
  std::ifstream in(path("bomb.mif.gz"), std::ios::binary);
  std::string compressed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  writeBytes(path("cut.mif.gz"), compressed.substr(0, compressed.size() / 2));
  try {
    imaging::readScalarImage(path("cut.mif.gz"));
    ADD_FAILURE() << "accepted";
  } catch (const ImageIoError& e) {
    EXPECT_NE(std::string(e.what()).find("cut short"), std::string::npos) << e.what();
  }
}

TEST_F(MrtrixFiles, TensorsAreReadInMrtrixOrderAlongTheScannerAxes) {
  // One voxel, D11 D22 D33 D12 D13 D23 = 3 2 1 0.5 0.25 0.125 in RAS; in LPS
  // the xy and xz couplings change sign (x and y flip), yz does not.
  const std::vector<float> components{3, 2, 1, 0.5f, 0.25f, 0.125f};
  writeBytes(path("dt.mif"), mifBytes("dim: 1,1,1,6\nvox: 2,2,2,1\nlayout: +1,+2,+3,+0\ndatatype: Float32LE\n" +
                                          kTransform,
                                      bytesOf(components, false)));
  const imaging::TensorReadResult read = imaging::readTensorVolume(path("dt.mif"));
  EXPECT_EQ(read.info.layout, imaging::TensorFileLayout::MrtrixSixVolumes);
  EXPECT_EQ(read.info.order, imaging::TensorOrder::Mrtrix);
  EXPECT_EQ(read.info.frame, imaging::TensorFrame::World);
  const SymTensor3 t = read.volume.tensors.at(0);
  EXPECT_EQ(t.xx, 3.f);
  EXPECT_EQ(t.yy, 2.f);
  EXPECT_EQ(t.zz, 1.f);
  EXPECT_EQ(t.xy, 0.5f);   // (-1)(-1) 0.5
  EXPECT_EQ(t.xz, -0.25f);
  EXPECT_EQ(t.yz, -0.125f);
  // A 4D image with other than six volumes is no tensor image.
  writeBytes(path("dwi.mif"), mifBytes("dim: 1,1,1,7\nvox: 2,2,2,1\nlayout: +0,+1,+2,+3\ndatatype: Float32LE\n",
                                       std::string(28, '\0')));
  EXPECT_THROW(imaging::readTensorVolume(path("dwi.mif")), ImageIoError);
}

TEST_F(MrtrixFiles, ScalarImagesWrittenAsMifReadBackOnTheSameGrid) {
  HandGeometry h;
  h.size = {4, 3, 2};
  h.spacing = {1.25, 2.0, 2.5};
  h.originLps = {-31.5, 12.25, 4.0};
  h.directionLps = rotation(1, 2, 3, 25);
  std::vector<float> values(24);
  for (std::size_t n = 0; n < values.size(); ++n) values[n] = 0.5f * float(n) - 3.f;
  for (const std::string name : {"d.mif", "d.mif.gz"}) {
    imaging::writeScalarImage(path(name), h.grid(), values);
    const imaging::ScalarImage back = imaging::readScalarImage(path(name));
    EXPECT_EQ(back.values, values) << name;
    EXPECT_EQ(imaging::geometryMismatch(back.geometry, h.grid()), "") << name;
  }
}

/// Parses `bytes` as a .mif file and expects one line naming the file that
/// says `problem`.
void expectRefused(const std::string& bytes, const std::string& problem) {
  try {
    imaging::parseMrtrixImage(bytes, "hostile.mif");
    ADD_FAILURE() << "accepted; expected: " << problem;
  } catch (const ImageIoError& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("hostile.mif: ", 0), 0u) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find(problem), std::string::npos) << message << " (expected: " << problem << ")";
  }
}

TEST(MrtrixHostileHeaders, AbsurdOrInconsistentSizesFailWithOneLineBeforeAnyLargeAllocation) {
  const std::string rest = "vox: 1,1,1\nlayout: +0,+1,+2\ndatatype: Float32LE\n";
  // 10^9 voxels declared, 16 bytes present: refused from the file size.
  expectRefused(mifBytes("dim: 1000,1000,1000\n" + rest, std::string(16, '\0')), "truncated");
  // Products that overflow 64 bits, or that no machine holds.
  expectRefused(mifBytes("dim: 4294967295,4294967295,4294967295\n" + rest, ""), "absurd");
  expectRefused(mifBytes("dim: 65536,65536,65536,65536\nvox: 1,1,1\nlayout: +0,+1,+2,+3\ndatatype: Float32LE\n", ""),
                "absurd");
  // Sizes that are no sizes.
  expectRefused(mifBytes("dim: 0,2,2\n" + rest, ""), "dim");
  expectRefused(mifBytes("dim: -2,2,2\n" + rest, ""), "dim");
  expectRefused(mifBytes("dim: 2,2,99999999999999999999\n" + rest, ""), "dim");
  // The grid must fit 32-bit voxel numbers, whatever the file holds.
  expectRefused(mifBytes("dim: 2048,2048,1025\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: Bit\n", ""), "32-bit");
  // Layouts that are no permutation, or do not match dim.
  expectRefused(mifBytes("dim: 2,2,2\nvox: 1,1,1\nlayout: +0,+0,+2\ndatatype: Float32LE\n", ""), "layout");
  expectRefused(mifBytes("dim: 2,2,2\nvox: 1,1,1\nlayout: +0,+1\ndatatype: Float32LE\n", ""), "layout");
  expectRefused(mifBytes("dim: 2,2,2\nvox: 1,1,1\nlayout: +0,+1,+7\ndatatype: Float32LE\n", ""), "layout");
  // Spacings, datatypes, transforms.
  expectRefused(mifBytes("dim: 2,2,2\nvox: 1,0,1\nlayout: +0,+1,+2\ndatatype: Float32LE\n", ""), "vox");
  expectRefused(mifBytes("dim: 2,2,2\nvox: 1,nan,1\nlayout: +0,+1,+2\ndatatype: Float32LE\n", ""), "vox");
  expectRefused(mifBytes("dim: 2,2,2\n" + std::string("vox: 1,1,1\nlayout: +0,+1,+2\ndatatype: CFloat32LE\n"), ""),
                "datatype");
  expectRefused(mifBytes("dim: 2,2,2\n" + rest + "transform: 1,0,0\n", ""), "transform");
  expectRefused(mifBytes("dim: 2,2,2\n" + rest + "transform: 1,0,0,0\ntransform: 1,0,0,0\ntransform: 0,0,1,0\n",
                         std::string(32, '\0')),
                "geometry");
  // The file entry and the header's end.
  expectRefused("mrtrix image\ndim: 2,2,2\n" + rest + "file: . 4\nEND\n" + std::string(32, '\0'), "inside the header");
  expectRefused("mrtrix image\ndim: 2,2,2\n" + rest + "file: . 99999999999999999999\nEND\n", "file");
  expectRefused("mrtrix image\ndim: 2,2,2\n" + rest + "file: . 200\nfile: . 300\nEND\n", "split over 2");
  expectRefused("mrtrix image\ndim: 2,2,2\n" + rest + "file: . 200\n", "no END");
  expectRefused("mrtrix image\n" + rest + "file: . 200\nEND\n", "no dim");
  expectRefused("mrtrix imagX\n", "not an MRtrix image");
  expectRefused("", "not an MRtrix image");
  expectRefused("mrtrix image\ndim 2,2,2\nEND\n", "line 2");
}

}  // namespace
}  // namespace stvd::testing

namespace stvd::testing {
namespace {

// MRtrix shows voxels in its own axis order (axes reordered and flipped to
// point right, anterior, superior); stvd says which voxel that is.
TEST(MrtrixVoxelIndex, FollowsMrtrixsReorderingOfTheAxes) {
  // LAS storage, as the shipped brain: i points left, so MRtrix counts it backwards.
  HandGeometry las;
  las.size = {112, 112, 32};
  las.directionLps = {1, 0, 0, 0, -1, 0, 0, 0, 1};  // i -> L, j -> A, k -> S
  EXPECT_EQ(imaging::mrtrixVoxelIndex(las.grid(), {55, 54, 15}), (std::array<long, 3>{56, 54, 15}));
  // Sagittal storage: i -> S, j -> P, k -> R; MRtrix's axes are (k, 9 - j, i).
  HandGeometry sagittal;
  sagittal.size = {8, 10, 12};
  sagittal.directionLps = {0, 0, -1, 0, 1, 0, 1, 0, 0};  // columns: (0,0,1), (0,1,0), (-1,0,0) in LPS
  const imaging::MrtrixAxisOrder order = imaging::mrtrixAxisOrder(sagittal.grid());
  EXPECT_EQ(order.axis, (std::array<int, 3>{2, 1, 0}));
  EXPECT_EQ(order.reversed, (std::array<bool, 3>{false, true, false}));
  EXPECT_EQ(imaging::mrtrixVoxelIndex(sagittal.grid(), {1, 2, 3}), (std::array<long, 3>{3, 7, 1}));
}

TEST(ToolInfoVoxel, PrintsTheIndexMrtrixShowsNextToStvds) {
  const ToolRun run = runTool({"info", sampleFile("dti_tensor_dipy5d.nii.gz"), "--voxel", "55,54,15"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  EXPECT_NE(run.out.find("MRtrix (mrview, mrconvert -coord) shows (111 - i, j, k)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("(55, 54, 15) in stvd = (56, 54, 15) in MRtrix, at RAS (6.39, 11.57, 76.31) mm"),
            std::string::npos)
      << run.out;
  const ToolRun outside = runTool({"info", sampleFile("dti_tensor_dipy5d.nii.gz"), "--voxel", "112,0,0"});
  EXPECT_EQ(outside.exitCode, 4) << outside.err;
}

}  // namespace
}  // namespace stvd::testing

namespace stvd::testing {
namespace {

class ToolMrtrix : public ScratchFolderTest {};

// The shipped tensors rewritten by hand as MRtrix stores dwi2tensor output
// (D11 D22 D33 D12 D13 D23 along the scanner's RAS axes, one volume per
// component, the first axis stored backwards) give the same distance map as
// the NIfTI file, and the map can be written as .mif.
TEST_F(ToolMrtrix, AMifTensorImageGivesTheSameDistancesAsTheNiftiItWasMadeFrom) {
  const imaging::TensorReadResult nifti = imaging::readTensorVolume(sampleFile("dti_tensor_dipy5d.nii.gz"));
  const GridGeometry& g = nifti.volume.geometry;
  const std::size_t n = g.voxelCount();
  std::vector<float> stored(6 * n);
  for (std::size_t k = 0, at = 0; k < g.size[2]; ++k)
    for (std::size_t j = 0; j < g.size[1]; ++j)
      for (std::size_t s = 0; s < g.size[0]; ++s, ++at) {
        const std::size_t i = g.size[0] - 1 - s;  // layout -0: the first axis backwards
        const SymTensor3 t = nifti.volume.tensors[i + g.size[0] * (j + g.size[1] * k)];
        // LPS -> RAS: x and y flip, so xz and yz change sign, xy does not.
        const float ras[6] = {t.xx, t.yy, t.zz, t.xy, -t.xz, -t.yz};
        for (int q = 0; q < 6; ++q) stored[at + n * q] = ras[q];
      }
  std::ostringstream lines;
  lines.precision(17);
  lines << "dim: " << g.size[0] << "," << g.size[1] << "," << g.size[2] << ",6\nvox: " << g.spacing[0] << ","
        << g.spacing[1] << "," << g.spacing[2] << ",1\nlayout: -0,+1,+2,+3\ndatatype: Float32LE\n";
  for (int r = 0; r < 3; ++r) {
    const double flip = r < 2 ? -1.0 : 1.0;
    lines << "transform: " << flip * g.direction[3 * r] << "," << flip * g.direction[3 * r + 1] << ","
          << flip * g.direction[3 * r + 2] << "," << flip * g.origin[r] << "\n";
  }
  writeBytes(path("dt.mif"), mifBytes(lines.str(), bytesOf(stored, false)));

  for (const std::string& input : {path("dt.mif"), sampleFile("dti_tensor_dipy5d.nii.gz")}) {
    const std::string output = input == path("dt.mif") ? path("from_mif.mif") : path("from_nifti.nii.gz");
    const ToolRun run =
        runTool({"distance", input, "--seed-voxel", "55,54,15", "--method", "dijkstra", "-o", output, "-q"});
    ASSERT_EQ(run.exitCode, 0) << run.err;
  }
  const imaging::ScalarImage a = imaging::readScalarImage(path("from_mif.mif"));
  const imaging::ScalarImage b = imaging::readScalarImage(path("from_nifti.nii.gz"));
  EXPECT_EQ(imaging::geometryMismatch(a.geometry, b.geometry), "");
  ASSERT_EQ(a.values.size(), b.values.size());
  double worst = 0.0;
  for (std::size_t v = 0; v < a.values.size(); ++v) worst = std::max(worst, double(std::abs(a.values[v] - b.values[v])));
  EXPECT_LT(worst, 1e-4);  // mm: float rounding of the frame change only
  EXPECT_EQ(b.values[55 + 112 * (54 + 112 * 15)], 0.f);
}

}  // namespace
}  // namespace stvd::testing
