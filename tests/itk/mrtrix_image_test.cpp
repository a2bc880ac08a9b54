// MRtrix image files (.mif, .mif.gz, .mih) written byte by byte here, as
// MRtrix's format description says, and read by stvd's own parser: layouts
// with reversed and permuted axes, every datatype family, scaling, the
// scanner transform, tensors in MRtrix's convention, and hostile headers
// that must fail with one line before any large allocation.
#include <gtest/gtest.h>

#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "known_field.hpp"
#include "stvd/errors.hpp"
#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/itk/scalar_image_io.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
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
// kept: a claim beyond what deflate can expand the file to fails at once;
// a claim within it, on a stream that holds less, fails after counting the
// stream without keeping it; so does a stream cut short.
TEST_F(MrtrixFiles, CompressedFilesThatHoldLessThanTheirHeaderDeclaresFailWithOneLine) {
  const auto compress = [&](const std::string& name, const std::string& bytes) {
    gzFile gz = gzopen(path(name).c_str(), "wb9");
    gzwrite(gz, bytes.data(), static_cast<unsigned>(bytes.size()));
    gzclose(gz);
  };
  const auto refusal = [&](const std::string& name) {
    try {
      imaging::readScalarImage(path(name));
    } catch (const ImageIoError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // 8 MiB of zeros (8 kB compressed) under a header that declares 4 GB.
  compress("bomb.mif.gz", mifBytes("dim: 1000,1000,1000\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: Float32LE\n",
                                   std::string(8 << 20, '\0')));
  EXPECT_NE(refusal("bomb.mif.gz").find("compressed bytes can hold"), std::string::npos) << refusal("bomb.mif.gz");
  // 1 MiB that does not compress, under a header that declares 2 MiB.
  std::string noise(1 << 20, '\0');
  std::uint32_t state = 12345;
  for (char& c : noise) c = static_cast<char>((state = state * 1664525u + 1013904223u) >> 24);
  compress("short.mif.gz",
           mifBytes("dim: 512,1024,1\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: Float32LE\n", noise));
  EXPECT_NE(refusal("short.mif.gz").find("truncated"), std::string::npos) << refusal("short.mif.gz");
  std::ifstream in(path("short.mif.gz"), std::ios::binary);
  std::string compressed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  writeBytes(path("cut.mif.gz"), compressed.substr(0, compressed.size() / 2));
  EXPECT_NE(refusal("cut.mif.gz").find("cut short"), std::string::npos) << refusal("cut.mif.gz");
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

/// The NIfTI voxel (as a linear index) whose centre is the physical point of
/// voxel (i, j, k) of `g`, or -1 when none is within a thousandth of a voxel.
long matchingVoxel(const GridGeometry& g, const GridGeometry& nifti, std::size_t i, std::size_t j, std::size_t k) {
  const Vec3d at = nifti.physicalPointToIndex(g.indexToPhysicalPoint(double(i), double(j), double(k)));
  const double c[3] = {at.x, at.y, at.z};
  long linear = 0;
  for (int a = 2; a >= 0; --a) {
    const double r = std::round(c[a]);
    if (std::abs(c[a] - r) > 1e-3 || r < 0 || r >= double(nifti.size[a])) return -1;
    linear = linear * long(nifti.size[a]) + long(r);
  }
  return linear;
}

// What `mrconvert dti_tensor_dipy5d.nii.gz dt5.mif` makes: five axes
// (112,112,32,1,6), the first stored backwards as in the NIfTI while MRtrix
// shows it reversed, DIPY's lower order in the NIfTI's voxel frame. It is
// read (it was refused as "not a tensor volume"), a default read in the
// mrtrix order stops at the component-order check, and with the order
// stated every tensor and every distance is the NIfTI's.
TEST_F(ToolMrtrix, AMifThatMrconvertMadeFromTheNifti5DTensorReadsAsTheNifti) {
  if (std::system("command -v mrconvert > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "mrconvert (MRtrix3) is not installed: the .mif it makes from a NIfTI 5D tensor is not tested";
  const std::string niftiPath = sampleFile("dti_tensor_dipy5d.nii.gz");
  const std::string command = "mrconvert -quiet '" + niftiPath + "' '" + path("dt5.mif") + "'";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const imaging::MrtrixImage mif = imaging::readMrtrixImage(path("dt5.mif"));
  ASSERT_EQ(mif.header.size, (std::vector<std::size_t>{112, 112, 32, 1, 6}));

  imaging::TensorReadOptions lower;
  lower.order = imaging::TensorOrder::Lower;
  const imaging::TensorReadResult fromMif = imaging::readTensorVolume(path("dt5.mif"), lower);
  const imaging::TensorReadResult nifti = imaging::readTensorVolume(niftiPath);
  EXPECT_EQ(fromMif.info.frame, imaging::TensorFrame::Voxel);
  const GridGeometry& g = fromMif.volume.geometry;
  double worst = 0.0;
  std::size_t compared = 0;
  for (std::size_t k = 0; k < g.size[2]; ++k)
    for (std::size_t j = 0; j < g.size[1]; ++j)
      for (std::size_t i = 0; i < g.size[0]; ++i) {
        const long at = matchingVoxel(g, nifti.volume.geometry, i, j, k);
        ASSERT_GE(at, 0) << "voxel " << i << "," << j << "," << k << " has no NIfTI voxel at its centre";
        const SymTensor3 a = fromMif.volume.tensors[i + g.size[0] * (j + g.size[1] * k)];
        const SymTensor3 b = nifti.volume.tensors[std::size_t(at)];
        const double scale = std::abs(b.xx) + std::abs(b.yy) + std::abs(b.zz);
        if (!(scale > 0)) continue;
        worst = std::max({worst, std::abs(a.xx - b.xx) / scale, std::abs(a.yy - b.yy) / scale,
                          std::abs(a.zz - b.zz) / scale, std::abs(a.xy - b.xy) / scale,
                          std::abs(a.xz - b.xz) / scale, std::abs(a.yz - b.yz) / scale});
        ++compared;
      }
  EXPECT_GT(compared, 100000u);
  EXPECT_LT(worst, 1e-5);  // float rounding of the frame change only

  // Read in MRtrix's order (the default), most tensors are not positive
  // definite: the run stops and names the option to check.
  const ToolRun unstated = runTool({"distance", path("dt5.mif"), "--seed-voxel", "56,54,15", "-o",
                                    path("unstated.nii.gz"), "-q"});
  EXPECT_EQ(unstated.exitCode, 3) << unstated.err;
  EXPECT_NE(unstated.err.find("--tensor-order"), std::string::npos) << unstated.err;
  EXPECT_FALSE(std::filesystem::exists(path("unstated.nii.gz")));

  // With the order stated, the distances of the NIfTI, voxel for voxel
  // (the .mif's first axis counts the other way: seed 111 - 55 = 56).
  ASSERT_EQ(runTool({"distance", path("dt5.mif"), "--tensor-order", "lower", "--seed-voxel", "56,54,15", "--method",
                     "dijkstra", "-o", path("from_mif.nii.gz"), "-q"}).exitCode, 0);
  ASSERT_EQ(runTool({"distance", niftiPath, "--seed-voxel", "55,54,15", "--method", "dijkstra", "-o",
                     path("from_nifti.nii.gz"), "-q"}).exitCode, 0);
  const imaging::ScalarImage a = imaging::readScalarImage(path("from_mif.nii.gz"));
  const imaging::ScalarImage b = imaging::readScalarImage(path("from_nifti.nii.gz"));
  double largest = 0.0;
  for (std::size_t k = 0; k < g.size[2]; ++k)
    for (std::size_t j = 0; j < g.size[1]; ++j)
      for (std::size_t i = 0; i < g.size[0]; ++i) {
        const float va = a.values[i + g.size[0] * (j + g.size[1] * k)];
        const float vb = b.values[std::size_t(matchingVoxel(a.geometry, b.geometry, i, j, k))];
        ASSERT_EQ(std::isfinite(va), std::isfinite(vb)) << i << "," << j << "," << k;
        if (std::isfinite(va)) largest = std::max(largest, double(std::abs(va - vb)));
      }
  EXPECT_LT(largest, 1e-3);  // mm
}

}  // namespace
}  // namespace stvd::testing

namespace stvd::testing {
namespace {

// MRtrix images are held to the rules every image format keeps
// (docs/reliability.md, "Inputs"): geometry within 1e6 mm, no size beyond
// the file or the machine, no device as data file, and the same data mean
// the same as in NIfTI and NRRD (a non-finite tensor component, exact
// integer labels, a tensor volume of one slice).
class MrtrixSameRules : public ScratchFolderTest {
 protected:
  void SetUp() override {
    ScratchFolderTest::SetUp();
    writeNiftiByHand(path("tensors.nii"), field.geometry, NiftiTensorLayout::SymMatrix5D,
                     std::vector<std::array<float, 6>>(field.voxelCount(), {1, 0, 1, 0, 0, 1}));
  }

  /// dim, vox, layout, datatype and transform lines of an image on
  /// `g` with `volumes` volumes (1: a 3D image).
  static std::string gridLines(const HandGeometry& hand, int volumes, const std::string& datatype) {
    const GridGeometry g = hand.grid();
    std::ostringstream lines;
    lines.precision(17);
    lines << "dim: " << g.size[0] << "," << g.size[1] << "," << g.size[2] << (volumes > 1 ? ",6" : "")
          << "\nvox: " << g.spacing[0] << "," << g.spacing[1] << "," << g.spacing[2] << (volumes > 1 ? ",1" : "")
          << "\nlayout: +0,+1,+2" << (volumes > 1 ? ",+3" : "") << "\ndatatype: " << datatype << "\n";
    for (int r = 0; r < 3; ++r) {
      const double flip = r < 2 ? -1.0 : 1.0;
      lines << "transform: " << flip * g.direction[3 * r] << "," << flip * g.direction[3 * r + 1] << ","
            << flip * g.direction[3 * r + 2] << "," << flip * g.origin[r] << "\n";
    }
    return lines.str();
  }

  /// An image on the field's grid, of ones (`volumes` 1) or of unit tensors
  /// (6), with the field `entry` (0-based) of the first header line
  /// starting with `key` replaced by `value`.
  std::string onesWithEntry(const std::string& name, int volumes, const std::string& key, int entry,
                            const std::string& value) {
    std::string lines = gridLines(field.geometry, volumes, "Float32LE");
    std::size_t at = lines.find(key) + key.size();
    for (int e = 0; e < entry; ++e) at = lines.find(',', at) + 1;
    lines.replace(at, lines.find_first_of(",\n", at) - at, value);
    std::vector<float> values(volumes * field.voxelCount(), 0.f);
    std::fill(values.begin(), values.begin() + std::min(volumes, 3) * field.voxelCount(), 1.f);  // D11 D22 D33
    writeBytes(path(name), mifBytes(lines, bytesOf(values, false)));
    return path(name);
  }

  /// Runs the tool and expects a one-line refusal naming `file` and
  /// mentioning `problem`, exit 3, and no output.
  void expectRefused(std::vector<std::string> arguments, const std::string& file, const std::string& problem) {
    arguments.insert(arguments.end(), {"-o", path("out.nii.gz"), "-q"});
    const ToolRun run = runTool(arguments);
    EXPECT_EQ(run.exitCode, 3) << run.err;
    EXPECT_EQ(run.err.find('\n'), run.err.size() - 1) << "not one line: " << run.err;
    EXPECT_EQ(run.err.rfind("stvd: " + file + ": ", 0), 0u) << run.err;
    EXPECT_NE(run.err.find(problem), std::string::npos) << run.err;
    EXPECT_FALSE(std::filesystem::exists(path("out.nii.gz")));
  }

  KnownField field;
};

TEST_F(MrtrixSameRules, GeometryThatIsNotFiniteOrBeyondAMillionMillimetresIsRefusedInEveryRole) {
  // Only the number named changes: the grid is otherwise the tensors' own,
  // so nothing else could refuse these files.
  const std::string seed = "--seed-voxel=5,4,3";
  const std::string far = onesWithEntry("far.mif", 1, "transform: ", 3, "1e17");
  expectRefused({"distance", path("tensors.nii"), seed, "--mask", far}, far,
                "transform entry (1, 4) is 1e+17, beyond the 1e+06 mm");
  expectRefused({"distance", path("tensors.nii"), "--seeds", far}, far, "transform entry (1, 4)");
  expectRefused({"connectivity", path("tensors.nii"), "--labels", far}, far, "transform entry (1, 4)");
  const std::string farTensors = onesWithEntry("far_tensors.mif", 6, "transform: ", 3, "-3e6");
  expectRefused({"distance", farTensors, seed}, farTensors, "transform entry (1, 4) is -3e+06, beyond the 1e+06 mm");
  const std::string wideTensors = onesWithEntry("wide_tensors.mif", 6, "vox: ", 0, "2e6");
  expectRefused({"distance", wideTensors, seed}, wideTensors, "the voxel size of axis 0 is 2e+06, beyond the 1e+06 mm");
  const std::string infinite = onesWithEntry("inf.mif", 1, "transform: ", 3, "inf");
  expectRefused({"distance", path("tensors.nii"), seed, "--mask", infinite}, infinite,
                "transform line 1 is not four finite numbers");
}

TEST_F(MrtrixSameRules, SizesBeyondTheMachineOrTheStreamAreRefusedAtOnce) {
  // 48 GB of float32 in a sparse file: the data are all there, but they
  // and their float copy would not fit in memory; refused before reading.
  const std::string header =
      mifBytes("dim: 1000,1000,1000,12\nvox: 1,1,1,1\nlayout: +0,+1,+2,+3\ndatatype: Float32LE\n", "");
  writeBytes(path("48gb.mif"), header);
  std::filesystem::resize_file(path("48gb.mif"), header.size() + 48'000'000'000ull);
  // 64 KiB of compressed zeros claiming 3.2 GB: more than deflate can expand
  // them to (1032 to 1), refused before anything is decompressed.
  const std::string claim =
      mifBytes("dim: 1000,1000,800\nvox: 1,1,1\nlayout: +0,+1,+2\ndatatype: Float32LE\n", std::string(1 << 20, '\0'));
  gzFile gz = gzopen(path("claim.mif.gz").c_str(), "wb9");
  gzwrite(gz, claim.data(), static_cast<unsigned>(claim.size()));
  gzclose(gz);
  // As the tensor input, refused for what the data would need; as a side
  // input (the mask), for its grid, from its header alone. Either at once:
  // little work, counted in processor time (which a loaded machine does not
  // stretch, as it does the time on the clock).
  const double start = toolProcessorSeconds();
  expectRefused({"distance", path("48gb.mif"), "--seed-voxel=5,4,3"}, path("48gb.mif"),
                "12000000000 values, which need 96 GB of memory");
  expectRefused({"distance", path("claim.mif.gz"), "--seed-voxel=5,4,3"}, path("claim.mif.gz"),
                "compressed bytes can hold");
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("48gb.mif")},
                path("48gb.mif"), "the mask is on another grid than " + path("tensors.nii") + " (size 1000x1000x1000");
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("claim.mif.gz")},
                path("claim.mif.gz"), "the mask is on another grid than " + path("tensors.nii") + " (size 1000x1000x800");
  EXPECT_LT(toolProcessorSeconds() - start, 10.0);
}

TEST_F(MrtrixSameRules, ADataFileThatIsADeviceIsRefused) {
  writeBytes(path("device.mih"), "mrtrix image\n" + gridLines(field.geometry, 1, "Float32LE") + "file: /dev/zero 0\n");
  expectRefused({"distance", path("tensors.nii"), "--seed-voxel=5,4,3", "--mask", path("device.mih")},
                path("device.mih"), "/dev/zero is not a regular file");
}

TEST_F(MrtrixSameRules, ANonFiniteTensorComponentMakesTheWholeTensorNaNAndNonFiniteMaskValuesStay) {
  const std::size_t n = field.voxelCount();
  std::vector<float> volumes(6 * n, 0.f);
  for (std::size_t v = 0; v < n; ++v) volumes[v] = volumes[v + n] = volumes[v + 2 * n] = 1.f;  // D11 D22 D33
  volumes[7 + 3 * n] = std::numeric_limits<float>::quiet_NaN();  // D12 of voxel 7
  volumes[8 + 5 * n] = std::numeric_limits<float>::infinity();   // D23 of voxel 8
  writeBytes(path("nan.mif"), mifBytes(gridLines(field.geometry, 6, "Float32LE"), bytesOf(volumes, false)));
  const imaging::TensorVolume v = imaging::readTensorVolume(path("nan.mif")).volume;
  for (const std::size_t voxel : {std::size_t{7}, std::size_t{8}}) {
    const SymTensor3& t = v.tensors[voxel];
    for (const float c : {t.xx, t.xy, t.xz, t.yy, t.yz, t.zz}) EXPECT_TRUE(std::isnan(c)) << "voxel " << voxel;
  }
  EXPECT_EQ(v.tensors[6].xx, 1.f);

  std::vector<float> mask(n, 1.f);
  mask[3] = std::numeric_limits<float>::quiet_NaN();
  mask[4] = -std::numeric_limits<float>::infinity();
  writeBytes(path("mask.mif"), mifBytes(gridLines(field.geometry, 1, "Float32LE"), bytesOf(mask, false)));
  const imaging::ScalarImage read = imaging::readScalarImage(path("mask.mif"));
  EXPECT_TRUE(std::isnan(read.values[3]));
  EXPECT_EQ(read.values[4], -std::numeric_limits<float>::infinity());
}

TEST_F(MrtrixSameRules, LabelsStayExactIntegers) {
  const std::size_t n = field.voxelCount();
  std::vector<std::int64_t> big(n, 0);
  big[0] = (std::int64_t{1} << 53) + 1;
  big[1] = -5;
  big[2] = std::int64_t{1} << 62;
  writeBytes(path("int64.mif"), mifBytes(gridLines(field.geometry, 1, "Int64BE"), bytesOf(big, true)));
  const imaging::LabelImage image = imaging::readLabelImage(path("int64.mif"));
  EXPECT_EQ(image.labels[0], (std::int64_t{1} << 53) + 1);
  EXPECT_EQ(image.labels[1], -5);
  EXPECT_EQ(image.labels[2], std::int64_t{1} << 62);

  const auto refusal = [&](const std::string& name) {
    try {
      imaging::readLabelImage(path(name));
    } catch (const ImageIoError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  std::vector<std::uint64_t> huge(n, 0);
  huge[4] = std::uint64_t{1} << 63;
  writeBytes(path("uint64.mif"), mifBytes(gridLines(field.geometry, 1, "UInt64LE"), bytesOf(huge, false)));
  EXPECT_NE(refusal("uint64.mif").find("label 9223372036854775808 at voxel (4, 0, 0) is beyond 2^63 - 1"),
            std::string::npos);
  std::vector<float> fraction(n, 0.f);
  fraction[4] = 2.5f;
  writeBytes(path("float.mif"), mifBytes(gridLines(field.geometry, 1, "Float32LE"), bytesOf(fraction, false)));
  EXPECT_NE(refusal("float.mif").find("voxel (4, 0, 0) holds 2.5, which is not an integer"), std::string::npos);
  // Integers scaled into fractions are no labels either.
  std::vector<std::uint8_t> stored(n, 0);
  stored[4] = 1;
  writeBytes(path("scaled.mif"),
             mifBytes(gridLines(field.geometry, 1, "UInt8") + "scaling: 0,0.5\n", bytesOf(stored, false)));
  EXPECT_NE(refusal("scaled.mif").find("voxel (4, 0, 0) holds 0.5"), std::string::npos);

  // Labels 16777216 and 16777217, one in float32, stay two regions.
  std::vector<std::int32_t> regions(n, 0);
  regions[1 + 11 * (1 + 9 * 1)] = 16777216;
  regions[8 + 11 * (6 + 9 * 5)] = 16777217;
  writeBytes(path("regions.mif"), mifBytes(gridLines(field.geometry, 1, "Int32LE"), bytesOf(regions, false)));
  const ToolRun run = runTool({"connectivity", path("tensors.nii"), "--labels", path("regions.mif"), "-o",
                               path("table.tsv"), "-q"});
  ASSERT_EQ(run.exitCode, 0) << run.err;
  std::ifstream table(path("table.tsv"));
  const std::string text((std::istreambuf_iterator<char>(table)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("16777216\t16777217"), std::string::npos) << text;
}

TEST_F(MrtrixSameRules, ATensorImageOfOneSliceIsAThinVolumeOnTheGridOfTheSameNifti) {
  HandGeometry thin = field.geometry;
  thin.size = {11, 9, 1};
  const std::size_t n = 11 * 9;
  std::vector<float> volumes(6 * n, 0.f);
  for (std::size_t v = 0; v < n; ++v) volumes[v] = volumes[v + n] = volumes[v + 2 * n] = 1.f;
  writeBytes(path("slice.mif"), mifBytes(gridLines(thin, 6, "Float32LE"), bytesOf(volumes, false)));
  writeNiftiByHand(path("slice.nii"), thin, NiftiTensorLayout::SymMatrix5D,
                   std::vector<std::array<float, 6>>(n, {1, 0, 1, 0, 0, 1}));
  const GridGeometry mif = imaging::readTensorVolume(path("slice.mif")).volume.geometry;
  const GridGeometry nifti = imaging::readTensorVolume(path("slice.nii")).volume.geometry;
  EXPECT_EQ(mif.size, (std::array<std::size_t, 3>{11, 9, 1}));
  EXPECT_EQ(imaging::geometryMismatch(mif, nifti), "");
  EXPECT_NEAR(mif.spacing[2], 2.0, 1e-12);
}

}  // namespace
}  // namespace stvd::testing
