// FOD images: the four spherical-harmonic bases against their closed forms
// and each other, orthonormality, the lmax of every coefficient count, the
// frames (a direction in LPS taken into the scanner's RAS or the voxel axes),
// and hostile files that must fail with one line naming the file. The
// comparison with DIPY and MRtrix themselves is tests/python/test_fod.py.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "stvd/errors.hpp"
#include "stvd/imaging/fod_field.hpp"
#include "stvd/imaging/spherical_harmonics.hpp"
#include "stvd/itk/fod_volume_io.hpp"
#include "test_support.hpp"

namespace stvd::testing {
namespace {

using namespace imaging;

const ShBasis kBases[] = {ShBasis::Tournier07, ShBasis::Tournier07Legacy, ShBasis::Descoteaux07,
                          ShBasis::Descoteaux07Legacy};

int shIndex(int l, int m) { return l * (l + 1) / 2 + m; }

TEST(SphericalHarmonics, DegreeTwoOfMrtrixBasisIsTheCartesianClosedForm) {
  // Real harmonics of degree 2 in Cartesian form, with the Condon-Shortley
  // phase that MRtrix3 (and scipy, hence DIPY) keep: the m = +-1 functions
  // carry a minus sign.
  const double x = 0.48, y = -0.6, z = 0.64;  // unit
  const std::vector<double> v = evaluateShBasis(ShBasis::Tournier07, 2, x, y, z);
  const double c = 0.5 * std::sqrt(15.0 / M_PI);
  EXPECT_NEAR(v[shIndex(0, 0)], 0.5 / std::sqrt(M_PI), 1e-14);
  EXPECT_NEAR(v[shIndex(2, -2)], c * x * y, 1e-14);
  EXPECT_NEAR(v[shIndex(2, -1)], -c * y * z, 1e-14);
  EXPECT_NEAR(v[shIndex(2, 0)], 0.25 * std::sqrt(5.0 / M_PI) * (3 * z * z - 1), 1e-14);
  EXPECT_NEAR(v[shIndex(2, 1)], -c * x * z, 1e-14);
  EXPECT_NEAR(v[shIndex(2, 2)], 0.5 * c * (x * x - y * y), 1e-14);
}

TEST(SphericalHarmonics, TheFourBasesDifferOnlyAsDocumented) {
  std::mt19937 rng(3);
  std::normal_distribution<double> n;
  for (int t = 0; t < 20; ++t) {
    const double x = n(rng), y = n(rng), z = n(rng);
    const auto t7 = evaluateShBasis(ShBasis::Tournier07, 12, x, y, z);
    const auto t7l = evaluateShBasis(ShBasis::Tournier07Legacy, 12, x, y, z);
    const auto d7 = evaluateShBasis(ShBasis::Descoteaux07, 12, x, y, z);
    const auto d7l = evaluateShBasis(ShBasis::Descoteaux07Legacy, 12, x, y, z);
    for (int l = 0; l <= 12; l += 2)
      for (int m = -l; m <= l; ++m) {
        const int j = shIndex(l, m);
        // Tournier: sqrt(2) between MRtrix3 and MRtrix 0.2 for m != 0.
        EXPECT_NEAR(t7[j], (m == 0 ? 1.0 : std::sqrt(2.0)) * t7l[j], 1e-12);
        // Descoteaux: (-1)^m for m < 0 between the paper's and DIPY's legacy.
        EXPECT_NEAR(d7[j], (m < 0 && (-m) % 2 ? -1.0 : 1.0) * d7l[j], 1e-12);
        // Tournier and Descoteaux (legacy) exchange the cosine and sine halves.
        EXPECT_NEAR(d7l[j], t7[shIndex(l, -m)], 1e-12);
      }
  }
}

/// Gauss-Legendre nodes and weights on [-1, 1].
void gaussLegendre(int n, std::vector<double>& x, std::vector<double>& w) {
  x.resize(n);
  w.resize(n);
  for (int i = 0; i < n; ++i) {
    double z = std::cos(M_PI * (i + 0.75) / (n + 0.5)), dp = 0;
    for (int it = 0; it < 100; ++it) {
      double p0 = 1, p1 = z;
      for (int k = 2; k <= n; ++k) {
        const double p2 = ((2 * k - 1) * z * p1 - (k - 1) * p0) / k;
        p0 = p1;
        p1 = p2;
      }
      dp = n * (z * p1 - p0) / (z * z - 1);
      const double dz = p1 / dp;
      z -= dz;
      if (std::abs(dz) < 1e-16) break;
    }
    x[i] = z;
    w[i] = 2 / ((1 - z * z) * dp * dp);
  }
}

TEST(SphericalHarmonics, BasesAreOrthonormalExceptMrtrix02s) {
  // Exact quadrature for products of degree <= 24: 14 Gauss-Legendre nodes
  // in cos(theta), 26 equal steps in phi.
  std::vector<double> ct, wt;
  gaussLegendre(14, ct, wt);
  const int nphi = 26, count = shCoefficientCount(12);
  for (ShBasis basis : kBases) {
    std::vector<double> gram(count * count, 0.0);
    for (std::size_t a = 0; a < ct.size(); ++a)
      for (int b = 0; b < nphi; ++b) {
        const double st = std::sqrt(1 - ct[a] * ct[a]), phi = 2 * M_PI * b / nphi;
        const auto y = evaluateShBasis(basis, 12, st * std::cos(phi), st * std::sin(phi), ct[a]);
        const double w = wt[a] * 2 * M_PI / nphi;
        for (int i = 0; i < count; ++i)
          for (int j = 0; j < count; ++j) gram[i * count + j] += w * y[i] * y[j];
      }
    for (int l = 0; l <= 12; l += 2)
      for (int m = -l; m <= l; ++m) {
        const int i = shIndex(l, m);
        const double expected = basis == ShBasis::Tournier07Legacy && m != 0 ? 0.5 : 1.0;
        EXPECT_NEAR(gram[i * count + i], expected, 1e-12) << shBasisName(basis) << " l " << l << " m " << m;
        for (int j = 0; j < count; ++j)
          if (j != i) {
            EXPECT_NEAR(gram[i * count + j], 0.0, 1e-12);
          }
      }
  }
}

TEST(SphericalHarmonics, CountsAndNames) {
  const int counts[] = {1, 6, 15, 28, 45, 66, 91};
  for (int l = 0; l <= 12; l += 2) {
    EXPECT_EQ(shCoefficientCount(l), counts[l / 2]);
    EXPECT_EQ(shDegreeOfCount(counts[l / 2]), l);
  }
  for (std::size_t c : {0, 2, 5, 7, 44, 46, 92, 120}) EXPECT_FALSE(shDegreeOfCount(c)) << c;
  for (ShBasis b : kBases) EXPECT_EQ(parseShBasis(shBasisName(b)), b);
  EXPECT_EQ(parseShBasis("mrtrix3"), ShBasis::Tournier07);
  EXPECT_EQ(parseShBasis("Descoteaux07-Legacy"), ShBasis::Descoteaux07Legacy);
  EXPECT_FALSE(parseShBasis("descoteaux"));
  EXPECT_EQ(defaultFodFrame("mrtrix3"), FodFrame::Scanner);
  EXPECT_EQ(defaultFodFrame("tournier07"), FodFrame::Voxel);
  EXPECT_THROW(evaluateShBasis(ShBasis::Tournier07, 14, 0, 0, 1), std::invalid_argument);
  EXPECT_THROW(evaluateShBasis(ShBasis::Tournier07, 8, 0, 0, 0), std::invalid_argument);
}

// --- Files -------------------------------------------------------------------

std::string mifWithData(const std::string& lines, const std::vector<float>& values) {
  std::string head = "mrtrix image\n" + lines + "datatype: Float32LE\n";
  std::size_t offset = (head.size() + 32 + 3) / 4 * 4;
  std::string header = head + "file: . " + std::to_string(offset) + "\nEND\n";
  header.resize(offset, ' ');
  std::string data(values.size() * 4, '\0');
  std::memcpy(data.data(), values.data(), data.size());
  return header + data;
}

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

class FodFiles : public ScratchFolderTest {};

std::string oneLineMessage(const std::function<void()>& f) {
  try {
    f();
  } catch (const ImageIoError& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.find('\n'), std::string::npos) << m;
    return m;
  }
  ADD_FAILURE() << "no ImageIoError";
  return "";
}

// A rotated, flipped scanner transform: RAS = R * diag(vox) * ijk + t.
const std::string kRotatedTransform =
    "transform: 0,-1,0,5\n"
    "transform: 0.6,0,0.8,-3\n"
    "transform: -0.8,0,0.6,7\n";

TEST_F(FodFiles, MrtrixImageIsMrtrix3BasisInTheScannerFrame) {
  const int count = 45;
  std::mt19937 rng(5);
  std::normal_distribution<float> n;
  std::vector<float> values(2 * 3 * 1 * count);
  for (float& v : values) v = n(rng);
  writeFile(path("fod.mif"), mifWithData("dim: 2,3,1,45\nvox: 2,2.5,3,1\nlayout: +0,+1,+2,+3\n" + kRotatedTransform,
                                         values));
  const FodField fod = readFodVolume(path("fod.mif"));
  EXPECT_EQ(fod.lmax, 8);
  EXPECT_EQ(fod.basis, ShBasis::Tournier07);
  EXPECT_EQ(fod.frame, FodFrame::Scanner);
  // The same through the imaging adapter's own reader, without ITK.
  EXPECT_EQ(readMrtrixFodVolume(path("fod.mif")).coefficients, fod.coefficients);
  // Voxel (1, 2, 0) is number 5; its coefficient j is volume j's value there.
  const std::size_t voxel = 5;
  for (int t = 0; t < 10; ++t) {
    const Vec3d lps{n(rng), n(rng), n(rng)};
    const double r = std::sqrt(lps.x * lps.x + lps.y * lps.y + lps.z * lps.z);
    // The scanner frame is RAS: x and y change sign, whatever the image axes.
    const auto y = evaluateShBasis(ShBasis::Tournier07, 8, -lps.x / r, -lps.y / r, lps.z / r);
    double expected = 0;
    for (int j = 0; j < count; ++j) expected += y[j] * values[voxel + 6 * j];
    EXPECT_NEAR(fod.amplitude(voxel, lps), expected, 1e-9 * (1 + std::abs(expected)));
  }
}

TEST_F(FodFiles, VoxelFrameFollowsTheIndexAxesInLps) {
  std::vector<float> values(6, 0.f);
  values[shIndex(2, 0)] = 1.f;  // Y_2^0: largest along the frame's z axis
  writeFile(path("fod.mif"), mifWithData("dim: 1,1,1,6\nvox: 1,1,1\nlayout: +0,+1,+2,+3\n" + kRotatedTransform,
                                         values));
  FodReadOptions options;
  options.frame = FodFrame::Voxel;
  const FodField fod = readFodVolume(path("fod.mif"), options);
  // The index axis k is RAS (0, 0.8, 0.6), LPS (0, -0.8, 0.6).
  const double along = fod.amplitude(0, {0, -0.8, 0.6});
  EXPECT_NEAR(along, std::sqrt(5.0 / (4 * M_PI)), 1e-6);
  EXPECT_NEAR(fod.amplitude(0, {0, 0.8, -0.6}), along, 1e-6);  // antipodal symmetry
  const FodField scanner = readFodVolume(path("fod.mif"));
  EXPECT_NEAR(scanner.amplitude(0, {0, 0, 1}), along, 1e-6);  // scanner z: superior
}

TEST_F(FodFiles, EveryCountOfVolumesGivesItsDegreeAndOthersFailInOneLine) {
  for (int count : {1, 6, 15, 28, 45, 66, 91, 2, 16, 44, 92}) {
    const std::string file = path("c" + std::to_string(count) + ".mif");
    writeFile(file, mifWithData("dim: 1,1,1," + std::to_string(count) + "\nvox: 1,1,1\nlayout: +0,+1,+2,+3\n",
                                std::vector<float>(count, 0.5f)));
    if (shDegreeOfCount(count)) {
      EXPECT_EQ(readFodVolume(file).lmax, *shDegreeOfCount(count));
    } else {
      const std::string m = oneLineMessage([&] { readFodVolume(file); });
      EXPECT_NE(m.find(file), std::string::npos) << m;
      EXPECT_NE(m.find(std::to_string(count) + " volumes"), std::string::npos) << m;
    }
  }
}

TEST_F(FodFiles, HostileFilesFailInOneLineNamingTheFile) {
  std::vector<float> values(2 * 15, 0.25f);
  values[16] = std::nanf("");  // volume-major, 2 voxels per volume: volume 8, voxel 0
  writeFile(path("nan.mif"), mifWithData("dim: 2,1,1,15\nvox: 1,1,1\nlayout: +0,+1,+2,+3\n", values));
  std::string m = oneLineMessage([&] { readFodVolume(path("nan.mif")); });
  EXPECT_NE(m.find(path("nan.mif")), std::string::npos) << m;
  EXPECT_NE(m.find("coefficient 8 of voxel (0, 0, 0) is NaN"), std::string::npos) << m;

  std::string bytes = mifWithData("dim: 2,1,1,15\nvox: 1,1,1\nlayout: +0,+1,+2,+3\n", std::vector<float>(30, 1.f));
  writeFile(path("short.mif"), bytes.substr(0, bytes.size() - 7));
  m = oneLineMessage([&] { readFodVolume(path("short.mif")); });
  EXPECT_NE(m.find(path("short.mif")), std::string::npos) << m;

  writeFile(path("3d.mif"), mifWithData("dim: 2,1,15\nvox: 1,1,1\nlayout: +0,+1,+2\n", std::vector<float>(30, 1.f)));
  m = oneLineMessage([&] { readFodVolume(path("3d.mif")); });
  EXPECT_NE(m.find("fourth axis"), std::string::npos) << m;

  FodReadOptions unknown;
  unknown.basis = "descoteaux";
  writeFile(path("ok.mif"), bytes);
  m = oneLineMessage([&] { readFodVolume(path("ok.mif"), unknown); });
  EXPECT_NE(m.find("unknown spherical-harmonic basis 'descoteaux'"), std::string::npos) << m;
}

TEST_F(FodFiles, NiftiNeedsItsBasisStatedAndTakesDipysVoxelFrame) {
  HandGeometry g;
  g.size = {2, 1, 1};
  g.directionLps = rotation(1, 2, 3, 40);
  std::vector<float> values(2 * 6, 0.f);
  values[2 * shIndex(2, 0)] = 1.f;  // voxel 0: Y_2^0
  writeScalarNiftiByHand(path("fod.nii"), g, values, 6);
  std::string m = oneLineMessage([&] { readFodVolume(path("fod.nii")); });
  EXPECT_NE(m.find("does not say its spherical-harmonic basis"), std::string::npos) << m;

  FodReadOptions dipy;
  dipy.basis = "descoteaux07_legacy";
  const FodField fod = readFodVolume(path("fod.nii"), dipy);
  EXPECT_EQ(fod.frame, FodFrame::Voxel);
  // The frame's z axis is the index axis k: column 2 of the LPS direction.
  const Matrix3& d = g.directionLps;
  EXPECT_NEAR(fod.amplitude(0, {d[2], d[5], d[8]}), std::sqrt(5.0 / (4 * M_PI)), 1e-6);

  writeScalarNiftiByHand(path("wrong.nii"), g, std::vector<float>(2 * 7, 0.f), 7);
  m = oneLineMessage([&] { readFodVolume(path("wrong.nii"), dipy); });
  EXPECT_NE(m.find("7 volumes is no spherical-harmonic count"), std::string::npos) << m;
  EXPECT_NE(m.find(path("wrong.nii")), std::string::npos) << m;

  writeScalarNiftiByHand(path("3d.nii"), g, std::vector<float>(2, 0.f));
  m = oneLineMessage([&] { readFodVolume(path("3d.nii"), dipy); });
  EXPECT_NE(m.find("fourth axis"), std::string::npos) << m;
}

}  // namespace
}  // namespace stvd::testing
