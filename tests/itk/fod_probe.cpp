// A test helper, not installed: reads an FOD image with stvd's reader and
// prints its amplitude at voxels and directions, so that the Python tests
// can hold stvd's evaluation to DIPY's and MRtrix's (tests/python/test_fod.py).
//
//   stvd_fod_probe FILE BASIS FRAME QUERIES
//   stvd_fod_probe FILE BASIS FRAME --path I J K TI TJ TK
//
// BASIS and FRAME as FodReadOptions takes them ("-": the file's default).
// QUERIES: a text file of lines "i j k x y z" (a voxel index and a direction
// in LPS). Prints one amplitude per line (%.17g). With --path: Dijkstra
// over the 26-neighbour grid under the convexified norm (fod_metric.hpp)
// from voxel (I, J, K); prints the distance of voxel (TI, TJ, TK) and then
// the voxels of its path, one "i j k" per line. Exit 3 with the reader's
// one-line message on standard error when the file is refused.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <string>

#include "stvd/errors.hpp"
#include "stvd/imaging/fod_metric.hpp"
#include "stvd/itk/fod_volume_io.hpp"
#include "stvd/propagation/predecessor_path.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"

int main(int argc, char** argv) {
  const bool path = argc == 11 && std::string(argv[4]) == "--path";
  if (argc != 5 && !path) {
    std::fprintf(stderr, "usage: stvd_fod_probe FILE BASIS FRAME QUERIES | --path I J K TI TJ TK\n");
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
    if (path) {
      const FodCostSampler sampler(fod, defaultFodSampling(fod.geometry));
      const FodStencilMetric metric = fodStencilMetric(sampler);
      const stvd::VoxelGridDomain domain(fod.geometry, stvd::Stencil::full26());
      const stvd::VertexId seed = domain.vertexAt(std::atoi(argv[5]), std::atoi(argv[6]), std::atoi(argv[7]));
      const stvd::VertexId target = domain.vertexAt(std::atoi(argv[8]), std::atoi(argv[9]), std::atoi(argv[10]));
      stvd::PropagationOptions options;
      options.method = stvd::Method::Dijkstra;
      const stvd::PropagationResult r = stvd::propagate(domain, metric, {seed}, options);
      std::printf("%.17g\n", r.distance[target]);
      const auto& g = fod.geometry;
      for (stvd::VertexId v : stvd::predecessorPath(r, target))
        std::printf("%zu %zu %zu\n", v % g.size[0], (v / g.size[0]) % g.size[1], v / (g.size[0] * g.size[1]));
      return 0;
    }
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
