#include "small_inputs.hpp"

#include <filesystem>
#include <fstream>
#include <sstream>

#include "known_field.hpp"
#include "kuhn_cube.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
#include "stvd/tetmesh/tet_mesh.hpp"
#include "stvd/tetmesh/tet_mesh_writers.hpp"

namespace fs = std::filesystem;

namespace stvd::testing {

FolderSnapshot snapshot(const std::string& folder) {
  FolderSnapshot files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    const std::string name = fs::relative(entry.path(), folder).string();
    if (entry.is_directory()) {
      files[name + "/"] = "";
      continue;
    }
    std::ifstream in(entry.path(), std::ios::binary);
    std::stringstream bytes;
    bytes << in.rdbuf();
    files[name] = bytes.str();
  }
  return files;
}

void SmallInputsTest::SetUp() {
  ScratchFolderTest::SetUp();
  fs::create_directory(path("in"));
  fs::create_directory(path("out"));
  const KnownField field;
  writeNiftiByHand(in("t.nii"), field.geometry, NiftiTensorLayout::SymMatrix5D,
                   std::vector<std::array<float, 6>>(
                       field.voxelCount(), {field.voxelFrameMetric.xx, field.voxelFrameMetric.xy,
                                            field.voxelFrameMetric.yy, field.voxelFrameMetric.xz,
                                            field.voxelFrameMetric.yz, field.voxelFrameMetric.zz}));
  writeScalarNiftiByHand(in("mask.nii"), field.geometry, std::vector<float>(field.voxelCount(), 1.f));
  std::vector<float> labels(field.voxelCount(), 0.f);
  for (int dk = -1; dk <= 1; ++dk)
    for (int dj = -1; dj <= 1; ++dj)
      for (int di = -1; di <= 1; ++di) {
        labels[field.linear({2 + di, 2 + dj, 2 + dk})] = 1.f;
        labels[field.linear({8 + di, 6 + dj, 4 + dk})] = 2.f;
      }
  writeScalarNiftiByHand(in("labels.nii"), field.geometry, labels);
  tetmesh::writeTetGenMesh(in("cube"), kuhnCube({0, 0, 0}, 1));
  {
    std::ofstream ply(in("square.ply"));
    ply << "ply\nformat ascii 1.0\nelement vertex 16\nproperty float x\nproperty float y\nproperty float z\n"
           "element face 9\nproperty list uchar int vertex_indices\nend_header\n";
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) ply << i << " " << j << " 0\n";
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const int a = i + 4 * j;
        ply << "4 " << a << " " << a + 1 << " " << a + 5 << " " << a + 4 << "\n";
      }
  }
  std::ofstream(in("tetra.stl"))
      << "solid tetra\n"
         "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
         "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
         "facet normal 0 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
         "facet normal 0 0 0\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\n"
         "endsolid tetra\n";
  writeMrtrixTensors();
  std::ofstream(in("box.off")) << "OFF\n8 6 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n"
                                  "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
}

void SmallInputsTest::writeMrtrixTensors() const {
  imaging::TensorWriteOptions mrtrix;
  mrtrix.layout = imaging::TensorFileLayout::MrtrixSixVolumes;
  mrtrix.order = imaging::TensorOrder::Mrtrix;
  mrtrix.frame = imaging::TensorFrame::World;
  imaging::writeTensorVolume(in("t.mif"), imaging::readTensorVolume(in("t.nii")).volume, mrtrix);
  // The same header without END, naming t.dat, which holds the data.
  std::ifstream mif(in("t.mif"), std::ios::binary);
  std::stringstream bytes;
  bytes << mif.rdbuf();
  const std::string all = bytes.str();
  const std::size_t file = all.find("file: . ");
  const std::size_t offset = std::stoul(all.substr(file + 8));
  std::ofstream(in("t.mih")) << all.substr(0, file) << "file: t.dat\n";
  std::ofstream(in("t.dat"), std::ios::binary) << all.substr(offset);
}

std::vector<std::string> SmallInputsTest::distanceRun(const std::string& output, const std::string& stats) const {
  std::vector<std::string> args{"distance", in("t.nii"), "--tensor-kind", "metric", "--seed-voxel", "5,4,3",
                                "--mask", in("mask.nii"), "-o", output, "-q"};
  if (!stats.empty()) args.insert(args.end(), {"--stats", stats});
  return args;
}

std::vector<std::string> SmallInputsTest::pathRun(const std::string& output, const std::string& table) const {
  return {"path", in("t.nii"), "--tensor-kind", "metric", "--seed-voxel", "5,4,3", "--targets", in("labels.nii"),
          "-o", output, "--tsv", table, "-q"};
}

std::vector<std::string> SmallInputsTest::connectivityRun(const std::string& output) const {
  return {"connectivity", in("t.nii"), "--tensor-kind", "metric", "--labels", in("labels.nii"), "-o", output, "-q"};
}

std::vector<std::string> SmallInputsTest::tetMeshRun(const std::string& output) const {
  return {"distance", in("cube.node"), "--seed-vertex", "1", "-o", output, "-q"};
}

std::vector<std::string> SmallInputsTest::surfaceRun(const std::string& output) const {
  return {"distance", in("square.ply"), "--seed-vertex", "0", "-o", output, "-q"};
}

std::vector<std::string> SmallInputsTest::tetrahedralizeRun(const std::string& base) const {
  return {"tetrahedralize", in("box.off"), "-o", base, "--max-volume", "0.01", "-q"};
}

bool SmallInputsTest::withTetrahedralize() {
#ifdef STVD_TEST_TETRAHEDRALIZE
  return true;
#else
  return false;
#endif
}

bool SmallInputsTest::withVdb() {
#ifdef STVD_TEST_VDB
  return true;
#else
  return false;
#endif
}

bool SmallInputsTest::withReports() {
#ifdef STVD_TEST_REPORTS
  return true;
#else
  return false;
#endif
}

}  // namespace stvd::testing
