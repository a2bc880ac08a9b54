// The imaging adapter of an installed stvd, without ITK: a diffusion tensor
// given in MRtrix's component order becomes the metric G = (D / MD)^-1, and
// the distance over a grid of it is checked against the exact answer; an
// MRtrix image written with gzip compression reads back bit for bit.
//   stvd_imaging_consumer [FOLDER]   (FOLDER: where the .mif.gz goes; default .)
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "stvd/imaging.hpp"
#include "stvd/stvd.hpp"

int main(int argc, char** argv) {
  using namespace stvd;
  const std::string folder = argc > 1 ? argv[1] : ".";

  // D = diag(1.7, 0.3, 0.3) e-3 mm^2/s along x, in MRtrix's order
  // xx, yy, zz, xy, xz, yz: MD = 0.767e-3, so G = MD diag(1/1.7, 1/0.3, 1/0.3).
  const float components[6] = {1.7e-3f, 0.3e-3f, 0.3e-3f, 0.f, 0.f, 0.f};
  const SymTensor3 d = imaging::tensorFromComponents(components, imaging::TensorOrder::Mrtrix);
  GridGeometry geometry;
  geometry.size = {21, 9, 9};
  const imaging::MetricFromTensors built =
      imaging::buildMetric(std::vector<SymTensor3>(geometry.voxelCount(), d), {}, imaging::MetricOptions{});
  const VoxelGridDomain domain(geometry, Stencil::full26());
  const RiemannianMetric metric(built.metric, &built.inDomain);
  const VertexId seed = domain.vertexAt(0, 4, 4), along = domain.vertexAt(20, 4, 4);
  const PropagationResult r = propagate(domain, metric, {seed});
  const double md = (1.7 + 0.3 + 0.3) / 3.0;
  const double exact = 20.0 * std::sqrt(md / 1.7);  // 20 mm along the fibre
  const double error = std::abs(r.distance[along] - exact) / exact;
  std::printf("distance along the fibre: %.5f mm (exact %.5f, relative error %.2g)\n", r.distance[along], exact,
              error);
  if (!(error < 1e-5)) {
    std::fprintf(stderr, "stvd_imaging_consumer: distance along the fibre off by %.3g\n", error);
    return 1;
  }

  // An MRtrix image round trip through zlib.
  const std::string path = folder + "/imaging_consumer_distance.mif.gz";
  std::vector<float> values(r.distance.begin(), r.distance.end());
  imaging::writeMrtrixImage(path, path, geometry, values);
  const imaging::MrtrixImage read = imaging::readMrtrixImage(path);
  if (read.values != values) {
    std::fprintf(stderr, "stvd_imaging_consumer: %s did not read back as written\n", path.c_str());
    return 1;
  }
  std::printf("%s: %zu values read back as written\n", path.c_str(), read.values.size());
  return 0;
}
