// The ITK file I/O of an installed stvd (component itk): a distance map
// written as NIfTI and as NRRD reads back with its grid and values.
//   stvd_itk_consumer [FOLDER]   (FOLDER: where the files go; default .)
#include <cstdio>
#include <string>
#include <vector>

#include "stvd/itk.hpp"

int main(int argc, char** argv) {
  using namespace stvd;
  const std::string folder = argc > 1 ? argv[1] : ".";
  GridGeometry geometry;
  geometry.size = {5, 4, 3};
  geometry.spacing = {1.0, 1.5, 2.0};
  geometry.origin = {-10.0, 20.0, 5.0};
  std::vector<float> values(geometry.voxelCount());
  for (std::size_t v = 0; v < values.size(); ++v) values[v] = 0.25f * static_cast<float>(v);
  for (const char* name : {"/itk_consumer.nii.gz", "/itk_consumer.nrrd"}) {
    const std::string path = folder + name;
    imaging::writeScalarImage(path, geometry, values);
    const imaging::ScalarImage read = imaging::readScalarImage(path);
    if (read.values != values || !imaging::geometryMismatch(read.geometry, geometry).empty()) {
      std::fprintf(stderr, "stvd_itk_consumer: %s did not read back as written\n", path.c_str());
      return 1;
    }
    std::printf("%s: %zu values and the grid read back as written\n", path.c_str(), values.size());
  }
  return 0;
}
