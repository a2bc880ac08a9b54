// A test helper, not installed: reads an FOD image with stvd's reader and
// prints its amplitude at voxels and directions, so that the Python tests
// can hold stvd's evaluation to DIPY's and MRtrix's (tests/python/test_fod.py).
//
//   stvd_fod_probe FILE BASIS FRAME QUERIES
//
// BASIS and FRAME as FodReadOptions takes them ("-": the file's default).
// QUERIES: a text file of lines "i j k x y z" (a voxel index and a direction
// in LPS). Prints one amplitude per line (%.17g). Exit 3 with the reader's
// one-line message on standard error when the file is refused.
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>

#include "stvd/errors.hpp"
#include "stvd/itk/fod_volume_io.hpp"

int main(int argc, char** argv) {
  if (argc != 5) {
    std::fprintf(stderr, "usage: stvd_fod_probe FILE BASIS FRAME QUERIES\n");
    return 2;
  }
  using namespace stvd::imaging;
  FodReadOptions options;
  if (std::string(argv[2]) != "-") options.basis = argv[2];
  if (std::string(argv[3]) != "-") {
    options.frame = parseFodFrame(argv[3]);
    if (!options.frame) {
      std::fprintf(stderr, "unknown frame %s\n", argv[3]);
      return 2;
    }
  }
  try {
    const FodField fod = readFodVolume(argv[1], options);
    std::printf("# lmax %d basis %s frame %s\n", fod.lmax, shBasisName(fod.basis).c_str(),
                fodFrameName(fod.frame).c_str());
    std::ifstream queries(argv[4]);
    long i, j, k;
    double x, y, z;
    const auto& g = fod.geometry;
    while (queries >> i >> j >> k >> x >> y >> z) {
      const std::size_t v = static_cast<std::size_t>(i) + g.size[0] * (static_cast<std::size_t>(j) +
                                                                     g.size[1] * static_cast<std::size_t>(k));
      std::printf("%.17g\n", fod.amplitude(v, stvd::Vec3d{x, y, z}));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 3;
  }
  return 0;
}
