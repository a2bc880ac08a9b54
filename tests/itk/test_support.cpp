#include "test_support.hpp"

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

namespace fs = std::filesystem;

namespace stvd::testing {

std::string sampleFile(const std::string& name) { return std::string(STVD_SAMPLE_DATA_DIR) + "/" + name; }

namespace {
std::atomic<int> scratchCounter{0};

fs::path uniqueTempPath(const std::string& stem) {
  return fs::temp_directory_path() /
         (stem + "_" + std::to_string(::getpid()) + "_" + std::to_string(scratchCounter++));
}
}  // namespace

void ScratchFolderTest::SetUp() {
  folder_ = uniqueTempPath("stvd_itk_test");
  fs::remove_all(folder_);
  fs::create_directories(folder_);
}

void ScratchFolderTest::TearDown() {
  std::error_code ec;
  fs::remove_all(folder_, ec);
}

std::vector<std::string> ScratchFolderTest::listFolder(const fs::path& folder) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(folder)) names.push_back(entry.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

// --- Linear algebra --------------------------------------------------------

Matrix3 rotation(double x, double y, double z, double degrees) {
  const double n = std::sqrt(x * x + y * y + z * z);
  x /= n;
  y /= n;
  z /= n;
  const double a = degrees * M_PI / 180.0, c = std::cos(a), s = std::sin(a), t = 1.0 - c;
  return {t * x * x + c,     t * x * y - s * z, t * x * z + s * y,
          t * x * y + s * z, t * y * y + c,     t * y * z - s * x,
          t * x * z - s * y, t * y * z + s * x, t * z * z + c};
}

Matrix3 transpose(const Matrix3& m) { return {m[0], m[3], m[6], m[1], m[4], m[7], m[2], m[5], m[8]}; }

Matrix3 multiply(const Matrix3& a, const Matrix3& b) {
  Matrix3 p{};
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      for (int k = 0; k < 3; ++k) p[3 * r + c] += a[3 * r + k] * b[3 * k + c];
  return p;
}

Matrix3 tensorMatrix(const SymTensor3& t) { return {t.xx, t.xy, t.xz, t.xy, t.yy, t.yz, t.xz, t.yz, t.zz}; }

SymTensor3 symmetricPart(const Matrix3& m) {
  return {static_cast<float>(m[0]), static_cast<float>(0.5 * (m[1] + m[3])),
          static_cast<float>(0.5 * (m[2] + m[6])), static_cast<float>(m[4]),
          static_cast<float>(0.5 * (m[5] + m[7])), static_cast<float>(m[8])};
}

SymTensor3 conjugateTranspose(const SymTensor3& t, const Matrix3& m) {
  return symmetricPart(multiply(transpose(m), multiply(tensorMatrix(t), m)));
}

double relativeDifference(const SymTensor3& a, const SymTensor3& b) {
  const double x[6] = {a.xx, a.xy, a.xz, a.yy, a.yz, a.zz};
  const double y[6] = {b.xx, b.xy, b.xz, b.yy, b.yz, b.zz};
  double scale = 0.0, diff = 0.0;
  for (int q = 0; q < 6; ++q) {
    scale = std::max(scale, std::abs(y[q]));
    diff = std::max(diff, std::abs(x[q] - y[q]));
  }
  return scale > 0.0 ? diff / scale : diff;
}

// --- Files ---------------------------------------------------------------------

GridGeometry HandGeometry::grid() const {
  GridGeometry g;
  for (int a = 0; a < 3; ++a) {
    g.size[a] = static_cast<std::size_t>(size[a]);
    g.spacing[a] = spacing[a];
    g.origin[a] = originLps[a];
  }
  g.direction = directionLps;
  return g;
}

namespace {

std::string vectorText(double x, double y, double z) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << x << "," << y << "," << z << ")";
  return s.str();
}

template <class T>
void put(std::vector<char>& bytes, std::size_t offset, T value) {
  std::memcpy(bytes.data() + offset, &value, sizeof(T));
}

}  // namespace

void writeTensorNrrdByHand(const std::string& path, const HandGeometry& g, const std::string& space,
                           const std::vector<SymTensor3>& components, const Matrix3* measurementFrameLps,
                           const std::vector<float>& confidence, bool gzip) {
  if (gzip) throw std::invalid_argument("the hand-written NRRD is raw only");
  const bool ras = space == "right-anterior-superior", las = space == "left-anterior-superior";
  const double flip[3] = {ras ? -1.0 : 1.0, ras || las ? -1.0 : 1.0, 1.0};  // LPS -> file space
  const bool masked = !confidence.empty();
  std::ofstream out(path, std::ios::binary);
  out << "NRRD0005\n# written by the stvd tests, byte by byte\n";
  out << "type: float\ndimension: 4\nspace: " << space << "\n";
  out << "sizes: " << (masked ? 7 : 6) << " " << g.size[0] << " " << g.size[1] << " " << g.size[2] << "\n";
  out << "space directions: none";
  for (int c = 0; c < 3; ++c)
    out << " "
        << vectorText(flip[0] * g.directionLps[c] * g.spacing[c], flip[1] * g.directionLps[3 + c] * g.spacing[c],
                      flip[2] * g.directionLps[6 + c] * g.spacing[c]);
  out << "\nkinds: " << (masked ? "3D-masked-symmetric-matrix" : "3D-symmetric-matrix") << " space space space\n";
  out << "endian: little\nencoding: raw\n";
  out << "space origin: "
      << vectorText(flip[0] * g.originLps[0], flip[1] * g.originLps[1], flip[2] * g.originLps[2]) << "\n";
  if (measurementFrameLps) {
    const Matrix3& m = *measurementFrameLps;
    out << "measurement frame:";
    for (int c = 0; c < 3; ++c)
      out << " " << vectorText(flip[0] * m[c], flip[1] * m[3 + c], flip[2] * m[6 + c]);
    out << "\n";
  }
  out << "\n";
  const std::size_t n = components.size();
  for (std::size_t v = 0; v < n; ++v) {
    const SymTensor3& t = components[v];
    const float values[7] = {masked ? confidence[v] : 0.f, t.xx, t.xy, t.xz, t.yy, t.yz, t.zz};
    out.write(reinterpret_cast<const char*>(masked ? values : values + 1),
              static_cast<std::streamsize>((masked ? 7 : 6) * sizeof(float)));
  }
}

namespace {

/// Quaternion (b, c, d) with a >= 0 of a proper rotation (Shepperd's method).
std::array<double, 3> quaternionOf(const Matrix3& r) {
  const double trace = r[0] + r[4] + r[8];
  double a, b, c, d;
  if (trace > 0) {
    const double s = 2.0 * std::sqrt(1.0 + trace);
    a = 0.25 * s;
    b = (r[7] - r[5]) / s;
    c = (r[2] - r[6]) / s;
    d = (r[3] - r[1]) / s;
  } else if (r[0] > r[4] && r[0] > r[8]) {
    const double s = 2.0 * std::sqrt(1.0 + r[0] - r[4] - r[8]);
    a = (r[7] - r[5]) / s;
    b = 0.25 * s;
    c = (r[1] + r[3]) / s;
    d = (r[2] + r[6]) / s;
  } else if (r[4] > r[8]) {
    const double s = 2.0 * std::sqrt(1.0 + r[4] - r[0] - r[8]);
    a = (r[2] - r[6]) / s;
    b = (r[1] + r[3]) / s;
    c = 0.25 * s;
    d = (r[5] + r[7]) / s;
  } else {
    const double s = 2.0 * std::sqrt(1.0 + r[8] - r[0] - r[4]);
    a = (r[3] - r[1]) / s;
    b = (r[2] + r[6]) / s;
    c = (r[5] + r[7]) / s;
    d = 0.25 * s;
  }
  if (a < 0) return {-b, -c, -d};
  return {b, c, d};
}

void writeNifti(const std::string& path, const HandGeometry& g, const std::array<std::int16_t, 8>& dim,
                std::int16_t intent, float intentP1, const std::vector<float>& data) {
  std::vector<char> header(352, 0);
  put<std::int32_t>(header, 0, 348);
  for (int i = 0; i < 8; ++i) put<std::int16_t>(header, 40 + 2 * i, dim[i]);
  put<float>(header, 56, intentP1);
  put<std::int16_t>(header, 68, intent);
  put<std::int16_t>(header, 70, 16);  // float32
  put<std::int16_t>(header, 72, 32);
  const float pixdim[8] = {1.f, float(g.spacing[0]), float(g.spacing[1]), float(g.spacing[2]), 1.f, 1.f, 1.f, 1.f};
  for (int i = 0; i < 8; ++i) put<float>(header, 76 + 4 * i, pixdim[i]);
  put<float>(header, 108, 352.f);
  put<float>(header, 112, 1.f);
  put<char>(header, 123, 10);  // mm, s
  put<std::int16_t>(header, 252, 1);
  put<std::int16_t>(header, 254, 1);
  // NIfTI geometry is RAS: flip the first two rows of the LPS geometry.
  Matrix3 rasDirection = g.directionLps;
  for (int c = 0; c < 3; ++c) {
    rasDirection[c] = -rasDirection[c];
    rasDirection[3 + c] = -rasDirection[3 + c];
  }
  const double originRas[3] = {-g.originLps[0], -g.originLps[1], g.originLps[2]};
  const auto q = quaternionOf(rasDirection);
  for (int i = 0; i < 3; ++i) put<float>(header, 256 + 4 * i, float(q[i]));
  for (int i = 0; i < 3; ++i) put<float>(header, 268 + 4 * i, float(originRas[i]));
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) put<float>(header, 280 + 16 * r + 4 * c, float(rasDirection[3 * r + c] * g.spacing[c]));
    put<float>(header, 280 + 16 * r + 12, float(originRas[r]));
  }
  std::memcpy(header.data() + 344, "n+1\0", 4);
  std::ofstream out(path, std::ios::binary);
  out.write(header.data(), static_cast<std::streamsize>(header.size()));
  out.write(reinterpret_cast<const char*>(data.data()), static_cast<std::streamsize>(data.size() * sizeof(float)));
}

}  // namespace

void writeNiftiByHand(const std::string& path, const HandGeometry& g, NiftiTensorLayout layout,
                      const std::vector<std::array<float, 6>>& perVoxel) {
  const std::size_t n = perVoxel.size();
  std::vector<float> data(6 * n);
  for (std::size_t v = 0; v < n; ++v)
    for (int c = 0; c < 6; ++c) data[v + n * c] = perVoxel[v][c];  // x fastest, the component axis slowest
  const auto nx = std::int16_t(g.size[0]), ny = std::int16_t(g.size[1]), nz = std::int16_t(g.size[2]);
  switch (layout) {
    case NiftiTensorLayout::SymMatrix5D:
      writeNifti(path, g, {5, nx, ny, nz, 1, 6, 1, 1}, 1005, 3.f, data);
      break;
    case NiftiTensorLayout::SixVolumes4D:
      writeNifti(path, g, {4, nx, ny, nz, 6, 1, 1, 1}, 0, 0.f, data);
      break;
    case NiftiTensorLayout::SixVector5DNoIntent:
      writeNifti(path, g, {5, nx, ny, nz, 1, 6, 1, 1}, 0, 0.f, data);
      break;
  }
}

void writeScalarNiftiByHand(const std::string& path, const HandGeometry& g, const std::vector<float>& values,
                            int volumes) {
  const auto nx = std::int16_t(g.size[0]), ny = std::int16_t(g.size[1]), nz = std::int16_t(g.size[2]);
  if (volumes > 1)
    writeNifti(path, g, {4, nx, ny, nz, std::int16_t(volumes), 1, 1, 1}, 0, 0.f, values);
  else
    writeNifti(path, g, {3, nx, ny, nz, 1, 1, 1, 1}, 0, 0.f, values);
}

// --- The executable ---------------------------------------------------------

namespace {
std::string shellQuote(const std::string& word) {
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

std::string slurp(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}
}  // namespace

std::string toolExecutable() {
  const char* other = std::getenv("STVD_TEST_EXECUTABLE");
  return other && *other ? other : STVD_EXECUTABLE;
}

namespace {

ToolRun runShellCommand(std::string command) {
  const fs::path capture = uniqueTempPath("stvd_tool_run");
  const fs::path outFile = capture.string() + ".out", errFile = capture.string() + ".err";
  command += " >" + shellQuote(outFile.string()) + " 2>" + shellQuote(errFile.string()) + " </dev/null";
  const int status = std::system(command.c_str());
  ToolRun run;
  run.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  run.out = slurp(outFile);
  run.err = slurp(errFile);
  std::error_code ec;
  fs::remove(outFile, ec);
  fs::remove(errFile, ec);
  return run;
}

}  // namespace

// A hang fails the test after ten minutes instead of stalling the suite:
// more than any run takes on a machine loaded twelve times over (the
// longest take seconds on a quiet one). STVD_TEST_TOOL_TIMEOUT (seconds)
// sets another bound, as scripts/sanitize.sh does for a tool built with the
// sanitizers, which runs several times slower.
std::string timeoutPrefix() {
  const char* seconds = std::getenv("STVD_TEST_TOOL_TIMEOUT");
  return "timeout -k 5 " + shellQuote(seconds && *seconds ? seconds : "600") + " ";
}

double toolProcessorSeconds() {
  struct rusage usage {};
  ::getrusage(RUSAGE_CHILDREN, &usage);
  return double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
}

ToolRun runTool(const std::vector<std::string>& arguments) {
  std::string command = timeoutPrefix() + shellQuote(toolExecutable());
  for (const std::string& a : arguments) command += " " + shellQuote(a);
  return runShellCommand(command);
}

ToolRun runToolInBash(const std::string& script, const std::vector<std::string>& arguments) {
  std::string command = timeoutPrefix() + "bash -c " + shellQuote(script) + " " + shellQuote(toolExecutable());
  for (const std::string& a : arguments) command += " " + shellQuote(a);
  return runShellCommand(command);
}

std::vector<std::map<std::string, std::string>> readTsv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> header;
  {
    std::istringstream h(line);
    std::string column;
    while (std::getline(h, column, '\t')) header.push_back(column);
  }
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(in, line)) {
    std::istringstream r(line);
    std::map<std::string, std::string> row;
    std::string value;
    for (std::size_t c = 0; std::getline(r, value, '\t'); ++c) row[header.at(c)] = value;
    rows.push_back(row);
  }
  return rows;
}

}  // namespace stvd::testing
