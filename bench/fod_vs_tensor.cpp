// The FOD metric's cost against the tensor metric's on the sample brain's
// grid (issue 35: the FOD table and its propagation within 3 times the tensor
// propagation at lmax 8).
//
//   stvd_fod_vs_tensor TENSORS --seed-voxel I,J,K [--threads N] [--reference-stride S] [--repeats R]
//
// The tensor metric and its domain are built as `stvd distance` builds them
// from the tensors (G = (D/MD)^-1, eigenvalue ratio capped at 100). The FOD
// is synthetic, on the same grid and domain, lmax 8 (MRtrix3's basis): in
// every domain voxel a lobe along the tensor's principal direction and, in
// the voxels of FA below 0.4 (where tensors are flat or round, most of them
// crossings in a real brain), a second lobe at 60 degrees to it, in the
// plane of the first two eigenvectors. The rows, all in one run:
//
//   tensor Dijkstra, tensor STVD (k = 6, the tool's default): the propagation
//   from the seed;
//   FOD table: fodStencilMetric on 1 thread and on N (default 2), with the
//   668 fixed sampling directions (the default before the caps);
//   FOD Dijkstra: the propagation from the seed over the table;
//   FOD segment table and FOD STVD (k = 6): what the tool's default for FOD
//   images computed before the caps (fodSegmentMetric, then STVD over it);
//   FOD table, 162 + 26 directions: a coarser sampling, for the record;
//   the same tables and propagations with the sampling adapted to each
//   voxel (defaultFodSampling, the tool's default: the coarse set and caps
//   around the maxima), and how far its table lies above the fixed one's
//   (never below: its points are a subset of theirs);
//   reference table: the simple computation the tests hold the table to
//   (convexifiedFodNormsReference), on every S-th domain voxel (default 64),
//   scaled to the domain: the table's cost before it was made fast.
//
// CPU seconds are the process's (all threads), wall seconds the clock's;
// ratios are to the tensor STVD propagation's CPU time, measured in the
// same run. Each propagation row is the run of median CPU time of R (default
// 1): a propagation takes a tenth of a second, where one run is at the mercy
// of the machine's other work; a table takes seconds and runs once.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <string>
#include <vector>

#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/fod_field.hpp"
#include "stvd/imaging/fod_metric.hpp"
#include "stvd/imaging/fod_segment_norm.hpp"
#include "stvd/imaging/spherical_harmonics.hpp"
#include "stvd/imaging/symmetric_eigen.hpp"
#include "stvd/imaging/tensor_metric.hpp"
#include "stvd/itk/tensor_volume_io.hpp"
#include "stvd/propagation/propagation.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace {

using namespace stvd;
using namespace stvd::imaging;

struct Times {
  double cpu = 0, wall = 0;
};

template <class Run>
Times timed(Run&& run) {
  const std::clock_t cpu = std::clock();
  const auto wall = std::chrono::steady_clock::now();
  run();
  return {double(std::clock() - cpu) / CLOCKS_PER_SEC,
          std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count()};
}

/// The run of median CPU time among `repeats` runs.
template <class Run>
Times timedMedian(int repeats, Run&& run) {
  std::vector<Times> t;
  for (int r = 0; r < repeats; ++r) t.push_back(timed(run));
  std::sort(t.begin(), t.end(), [](const Times& a, const Times& b) { return a.cpu < b.cpu; });
  return t[t.size() / 2];
}

/// Adds a lobe along the LPS direction d (h_l Y_lm(d), largest at d).
void addLobe(const FodField& f, float* c, const Vec3d& d, double weight) {
  const Vec3d s = f.toShFrame(d);
  const std::vector<double> y = evaluateShBasis(ShBasis::Tournier07, 8, s.x, s.y, s.z);
  for (int l = 0; l <= 8; l += 2)
    for (int m = -l; m <= l; ++m) {
      const int j = l * (l + 1) / 2 + m;
      c[j] += static_cast<float>(weight * std::exp(-0.02 * l * (l + 1)) * y[j]);
    }
}

int usage() {
  std::fprintf(stderr, "usage: stvd_fod_vs_tensor TENSORS --seed-voxel I,J,K [--threads N] [--reference-stride S] [--repeats R]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) return usage();
  const std::string path = argv[1];
  std::array<int, 3> seed{-1, -1, -1};
  unsigned threads = 2;
  std::size_t stride = 64;
  int repeats = 1;
  for (int a = 2; a < argc; ++a) {
    if (!std::strcmp(argv[a], "--seed-voxel") && a + 1 < argc) {
      if (std::sscanf(argv[++a], "%d,%d,%d", &seed[0], &seed[1], &seed[2]) != 3) return usage();
    } else if (!std::strcmp(argv[a], "--threads") && a + 1 < argc) {
      threads = static_cast<unsigned>(std::atoi(argv[++a]));
    } else if (!std::strcmp(argv[a], "--repeats") && a + 1 < argc) {
      repeats = std::max(1, std::atoi(argv[++a]));
    } else if (!std::strcmp(argv[a], "--reference-stride") && a + 1 < argc) {
      stride = static_cast<std::size_t>(std::max(1, std::atoi(argv[++a])));
    } else {
      return usage();
    }
  }
  if (seed[0] < 0) return usage();

  const TensorReadResult read = readTensorVolume(path);
  const MetricFromTensors built = buildMetric(read.volume.tensors, {}, MetricOptions{});
  const GridGeometry& g = read.volume.geometry;
  const VoxelGridDomain domain(g, Stencil::full26(), built.inDomain);
  const RiemannianMetric tensorMetric(built.metric, &built.inDomain);
  const VertexId source = domain.vertexAt(seed[0], seed[1], seed[2]);
  std::size_t domainVoxels = 0;
  for (std::uint8_t inside : built.inDomain) domainVoxels += inside != 0;

  // The synthetic FOD on the same grid and domain.
  FodField fod;
  fod.geometry = g;
  fod.lmax = 8;
  fod.basis = ShBasis::Tournier07;
  fod.frame = FodFrame::Scanner;
  fod.lpsToShFrame = lpsToFodFrame(FodFrame::Scanner, g);
  fod.coefficients.assign(g.voxelCount() * 45, 0.f);
  std::size_t crossings = 0;
  for (std::size_t v = 0; v < g.voxelCount(); ++v) {
    if (!built.inDomain[v]) continue;
    const SymmetricEigen e = eigenDecompose(read.volume.tensors[v]);
    float* c = fod.coefficients.data() + v * 45;
    addLobe(fod, c, e.vectors[0], 1.0);
    if (fractionalAnisotropy(e.values) < 0.4) {
      const double t = 60 * M_PI / 180;
      addLobe(fod, c, std::cos(t) * e.vectors[0] + std::sin(t) * e.vectors[1], 0.8);
      ++crossings;
    }
  }

  PropagationOptions dijkstra;
  dijkstra.method = Method::Dijkstra;
  PropagationOptions stvd;  // the tool's default: STVD, k = 6
  stvd.method = Method::ShortTermVectorDijkstra;
  const Times tensorDijkstra = timedMedian(repeats, [&] { propagate(domain, tensorMetric, {source}, dijkstra); });
  const Times tensorStvd = timedMedian(repeats, [&] { propagate(domain, tensorMetric, {source}, stvd); });

  const FodCostSampler sampler(fod, defaultFodSamplingDirections(g));
  FodStencilMetric fodMetric = fodStencilMetric(sampler, &built.inDomain, 1);  // warm-up (pages, caches)
  const Times tableOne = timed([&] { fodMetric = fodStencilMetric(sampler, &built.inDomain, 1); });
  const Times tableMany = timed([&] { fodMetric = fodStencilMetric(sampler, &built.inDomain, threads); });
  const Times fodDijkstra = timedMedian(repeats, [&] { propagate(domain, fodMetric, {source}, dijkstra); });
  FodSegmentMetric segmentMetric = fodSegmentMetric(sampler, &built.inDomain, 1);
  const Times segmentTable = timed([&] { segmentMetric = fodSegmentMetric(sampler, &built.inDomain, 1); });
  const Times fodStvd = timedMedian(repeats, [&] { propagate(domain, segmentMetric, {source}, stvd); });
  // A coarser sampling (162 + 26 directions): fewer points of the ball, so
  // a larger gauge (never a smaller one) for less work; not what the tool
  // computes, measured for the record.
  const FodCostSampler coarse(fod, defaultFodSamplingDirections(g, 2));
  const Times tableCoarse = timed([&] { fodStencilMetric(coarse, &built.inDomain, 1); });
  // The sampling adapted to each voxel (162 + 26 directions and caps of the
  // 2562-direction icosphere around the maxima: adaptiveFodSampling), both
  // tables and their propagations.
  const FodCostSampler caps(fod, defaultFodSampling(g));
  FodStencilMetric capsMetric = fodStencilMetric(caps, &built.inDomain, 1);
  const Times capsTable = timed([&] { capsMetric = fodStencilMetric(caps, &built.inDomain, 1); });
  const Times capsDijkstra = timedMedian(repeats, [&] { propagate(domain, capsMetric, {source}, dijkstra); });
  FodSegmentMetric capsSegment = fodSegmentMetric(caps, &built.inDomain, 1);
  const Times capsSegmentTable = timed([&] { capsSegment = fodSegmentMetric(caps, &built.inDomain, 1); });
  const Times capsStvd = timedMedian(repeats, [&] { propagate(domain, capsSegment, {source}, stvd); });
  double capsAbove = 0, capsBelow = 0;
  std::size_t capsDiffer = 0;
  for (std::size_t v = 0; v < g.voxelCount(); ++v)
    for (int q = 0; q < 26; ++q) {
      const double r = double(capsMetric[v].cost[q]) / fodMetric[v].cost[q] - 1;
      capsAbove = std::max(capsAbove, r);
      capsBelow = std::min(capsBelow, r);
      capsDiffer += r != 0;
    }

  // The reference computation on every stride-th domain voxel, as a field
  // of those voxels alone.
  FodField sample;
  sample.lmax = 8;
  sample.basis = fod.basis;
  sample.frame = fod.frame;
  sample.lpsToShFrame = fod.lpsToShFrame;
  sample.geometry = g;
  std::size_t seen = 0;
  for (std::size_t v = 0; v < g.voxelCount(); ++v)
    if (built.inDomain[v] && seen++ % stride == 0)
      sample.coefficients.insert(sample.coefficients.end(), fod.coefficients.begin() + 45 * v,
                                 fod.coefficients.begin() + 45 * (v + 1));
  const std::size_t sampled = sample.coefficients.size() / 45;
  sample.geometry.size = {sampled, 1, 1};
  sample.geometry.direction = g.direction;
  const FodCostSampler sampleSampler(sample, defaultFodSamplingDirections(g));
  const std::vector<Vec3d> queries = neighbourDirections26(g);
  std::vector<float> reference, fast;
  const Times referenceSample = timed([&] { reference = convexifiedFodNormsReference(sampleSampler, queries); });
  const Times fastSample = timed([&] { fast = convexifiedFodTable(sampleSampler, queries); });
  double worst = 0;
  for (std::size_t i = 0; i < fast.size(); ++i)
    worst = std::max(worst, std::abs(double(fast[i]) - reference[i]) / reference[i]);

  std::printf("grid %zu x %zu x %zu, %zu domain voxels (%zu with two lobes), lmax 8, %zu sampling directions\n",
              g.size[0], g.size[1], g.size[2], domainVoxels, crossings, sampler.directions().size());
  std::printf("%-34s %9s %9s %12s %14s\n", "", "CPU s", "wall s", "CPU us/vox", "CPU / tensor STVD");
  auto row = [&](const char* name, const Times& t, double voxels) {
    std::printf("%-34s %9.3f %9.3f %12.2f %14.2f\n", name, t.cpu, t.wall, 1e6 * t.cpu / voxels, t.cpu / tensorStvd.cpu);
  };
  const double d = double(domainVoxels);
  row("tensor Dijkstra", tensorDijkstra, d);
  row("tensor STVD k=6", tensorStvd, d);
  row("FOD table (668 fixed), 1 thread", tableOne, d);
  const std::string many = "FOD table (668 fixed), " + std::to_string(threads) + " threads";
  row(many.c_str(), tableMany, d);
  row("FOD Dijkstra", fodDijkstra, d);
  const Times total{tableOne.cpu + fodDijkstra.cpu, tableOne.wall + fodDijkstra.wall};
  row("FOD table (1 thread) + Dijkstra", total, d);
  const Times totalMany{tableMany.cpu + fodDijkstra.cpu, tableMany.wall + fodDijkstra.wall};
  const std::string manyTotal = "FOD table (" + std::to_string(threads) + " threads) + Dijkstra";
  row(manyTotal.c_str(), totalMany, d);
  row("FOD segment table, 1 thread", segmentTable, d);
  row("FOD STVD k=6", fodStvd, d);
  const Times totalStvd{segmentTable.cpu + fodStvd.cpu, segmentTable.wall + fodStvd.wall};
  row("FOD segment table + STVD (before)", totalStvd, d);
  row("FOD table, 162 + 26 directions", tableCoarse, d);
  row("FOD table, caps (default)", capsTable, d);
  row("FOD Dijkstra over it", capsDijkstra, d);
  const Times capsTotal{capsTable.cpu + capsDijkstra.cpu, capsTable.wall + capsDijkstra.wall};
  row("FOD table, caps + Dijkstra", capsTotal, d);
  row("FOD segment table, caps (default)", capsSegmentTable, d);
  row("FOD STVD k=6 over it", capsStvd, d);
  const Times capsTotalStvd{capsSegmentTable.cpu + capsStvd.cpu, capsSegmentTable.wall + capsStvd.wall};
  row("FOD segment table, caps + STVD", capsTotalStvd, d);
  const double scale = d / double(sampled);
  const Times referenceScaled{referenceSample.cpu * scale, referenceSample.wall * scale};
  const Times fastScaled{fastSample.cpu * scale, fastSample.wall * scale};
  const std::string referenceName = "reference table (1/" + std::to_string(stride) + ", scaled)";
  row(referenceName.c_str(), referenceScaled, d);
  const std::string fastName = "fast table (same voxels, scaled)";
  row(fastName.c_str(), fastScaled, d);
  std::printf("FOD table + Dijkstra against the tensor STVD propagation: %.1f x (CPU), %.1f x (wall, %u threads)\n",
              total.cpu / tensorStvd.cpu, totalMany.wall / tensorStvd.wall, threads);
  std::printf("FOD segment table + STVD (the default before the caps) against the tensor STVD propagation: %.1f x (CPU)\n",
              totalStvd.cpu / tensorStvd.cpu);
  std::printf("with the caps (the tool's default): table + Dijkstra %.1f x, segment table + STVD %.1f x (CPU)\n",
              capsTotal.cpu / tensorStvd.cpu, capsTotalStvd.cpu / tensorStvd.cpu);
  std::printf("caps table against the fixed one's: %zu of %zu values differ, by %.3g to %.3g (relative)\n", capsDiffer,
              26 * g.voxelCount(), capsBelow, capsAbove);
  std::printf("fast table against the reference: %.1f x less CPU; largest relative difference %.3g (%zu voxels)\n",
              referenceSample.cpu / fastSample.cpu, worst, sampled);
  return 0;
}
