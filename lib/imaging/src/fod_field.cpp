#include "stvd/imaging/fod_field.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <stdexcept>

#include "stvd/errors.hpp"
#include "stvd/imaging/mrtrix_image.hpp"

namespace stvd::imaging {

std::optional<FodFrame> parseFodFrame(const std::string& name) {
  std::string n = name;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (n == "scanner" || n == "world") return FodFrame::Scanner;
  if (n == "voxel") return FodFrame::Voxel;
  return std::nullopt;
}

std::string fodFrameName(FodFrame frame) { return frame == FodFrame::Scanner ? "scanner" : "voxel"; }

FodFrame defaultFodFrame(const std::string& basisName) {
  std::string n = basisName;
  std::transform(n.begin(), n.end(), n.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return n == "mrtrix3" ? FodFrame::Scanner : FodFrame::Voxel;
}

Matrix3 lpsToFodFrame(FodFrame frame, const GridGeometry& geometry) {
  if (frame == FodFrame::Scanner) return rasToLps();
  const Matrix3 axes = voxelAxes(geometry);  // columns: the index axes in LPS
  Matrix3 t{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) t[3 * r + c] = axes[3 * c + r];
  return t;
}

Vec3d FodField::toShFrame(const Vec3d& d) const {
  const Matrix3& m = lpsToShFrame;
  Vec3d s{m[0] * d.x + m[1] * d.y + m[2] * d.z, m[3] * d.x + m[4] * d.y + m[5] * d.z,
          m[6] * d.x + m[7] * d.y + m[8] * d.z};
  const double n = std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
  if (!(n > 0.0) || !std::isfinite(n)) throw std::invalid_argument("FOD amplitude: the direction is zero or not finite");
  return {s.x / n, s.y / n, s.z / n};
}

double FodField::amplitude(std::size_t v, const Vec3d& directionLps) const {
  const Vec3d s = toShFrame(directionLps);
  double y[91];
  evaluateShBasis(basis, lmax, s.x, s.y, s.z, y);
  const float* c = voxelCoefficients(v);
  double a = 0.0;
  for (int j = 0, n = coefficientCount(); j < n; ++j) a += y[j] * c[j];
  return a;
}

int fodDegreeOfVolumes(const std::string& name, std::size_t volumes) {
  const std::optional<int> lmax = shDegreeOfCount(volumes);
  if (!lmax)
    throw ImageIoError(name, "not an FOD image: " + std::to_string(volumes) +
                                 " volumes is no spherical-harmonic count of even lmax 0 to 12 "
                                 "(1, 6, 15, 28, 45, 66 or 91 volumes)");
  return *lmax;
}

FodField fodFieldFromVolumes(const std::string& name, const GridGeometry& geometry, const float* values,
                             std::size_t valueCount, std::size_t volumes, ShBasis basis, FodFrame frame,
                             const Matrix3& lpsToShFrame) {
  const int lmax = fodDegreeOfVolumes(name, volumes);
  const std::size_t n = geometry.voxelCount();
  if (valueCount != n * volumes)
    throw ImageIoError(name, "holds " + std::to_string(valueCount) + " values, expected " + std::to_string(volumes) +
                                 " per voxel for " + std::to_string(n) + " voxels");
  FodField f;
  f.geometry = geometry;
  f.lmax = lmax;
  f.basis = basis;
  f.frame = frame;
  f.lpsToShFrame = lpsToShFrame;
  f.coefficients.resize(valueCount);
  for (std::size_t j = 0; j < volumes; ++j) {
    const float* volume = values + j * n;
    for (std::size_t v = 0; v < n; ++v) {
      const float c = volume[v];
      if (!std::isfinite(c)) {
        const std::size_t i = v % geometry.size[0], jj = (v / geometry.size[0]) % geometry.size[1],
                          k = v / (geometry.size[0] * geometry.size[1]);
        throw ImageIoError(name, std::string("coefficient ") + std::to_string(j) + " of voxel (" + std::to_string(i) +
                                     ", " + std::to_string(jj) + ", " + std::to_string(k) + ") is " +
                                     (std::isnan(c) ? "NaN" : "infinite"));
      }
      f.coefficients[v * volumes + j] = c;
    }
  }
  return f;
}

ShBasis shBasisOfFile(const std::string& path, const std::string& name) {
  const std::optional<ShBasis> basis = parseShBasis(name);
  if (!basis)
    throw ImageIoError(path, "unknown spherical-harmonic basis '" + name + "' (one of " + shBasisNames() + ")");
  return *basis;
}

namespace {

std::string dimensionsText(const std::vector<std::size_t>& size) {
  std::string dim;
  for (std::size_t s : size) dim += (dim.empty() ? "" : ",") + std::to_string(s);
  return dim;
}

}  // namespace

/// An MRtrix image X Y Z N, as dwi2fod and amp2sh write it: MRtrix3's basis
/// in the scanner frame unless stated.
FodField readMrtrixFodVolume(const std::string& path, const FodReadOptions& options) {
  const MrtrixImage image = readMrtrixImage(path);
  const std::vector<std::size_t>& size = image.header.size;
  if (size.size() != 4)
    throw ImageIoError(path, "not an FOD image: spherical-harmonic coefficients lie along a fourth axis "
                             "(dim X,Y,Z,N), this image has dim " + dimensionsText(size));
  const ShBasis basis = options.basis.empty() ? ShBasis::Tournier07 : shBasisOfFile(path, options.basis);
  const FodFrame frame = options.frame.value_or(FodFrame::Scanner);
  // The voxel frame of an MRtrix image is its axes as stored (as for
  // tensors: a file mrconvert made from a NIfTI file keeps that file's axes).
  Matrix3 lpsToSh = lpsToFodFrame(frame, image.geometry);
  if (frame == FodFrame::Voxel) {
    const Matrix3 axes = mrtrixStoredVoxelAxes(image.header, image.geometry);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) lpsToSh[3 * r + c] = axes[3 * c + r];
  }
  return fodFieldFromVolumes(path, image.geometry, image.values.data(), image.values.size(), size[3], basis, frame,
                             lpsToSh);
}

}  // namespace stvd::imaging
