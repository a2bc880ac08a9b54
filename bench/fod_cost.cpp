// The precomputation of the FOD cost (docs/fod.md): per voxel at lmax 8,
// the amplitudes along the 668 sampling directions (642 of a subdivided
// icosahedron and the 26 neighbour directions) and the convexified norm F*
// along the 26 neighbour directions (the simplex gauge of the hull of the
// cost's sampled unit ball), and the same by the simple computation the
// tests hold it to (the "Reference" rows), and with the sampling adapted to
// each voxel (the "Caps" rows). Voxels hold two fibres crossing
// at angles from 30 to 90 degrees in random planes. Counter: cpu_per_voxel
// (seconds).
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>
#include <vector>

#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/fod_metric.hpp"
#include "stvd/imaging/spherical_harmonics.hpp"

namespace {

using namespace stvd;
using namespace stvd::imaging;

Vec3d randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n;
  Vec3d v{n(rng), n(rng), n(rng)};
  const double l = std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return {v.x / l, v.y / l, v.z / l};
}

FodField crossings(std::size_t voxels) {
  FodField f;
  f.geometry.size = {voxels, 1, 1};
  f.lmax = 8;
  f.basis = ShBasis::Tournier07;
  f.frame = FodFrame::Scanner;
  f.lpsToShFrame = lpsToFodFrame(FodFrame::Scanner, f.geometry);
  f.coefficients.assign(voxels * 45, 0.f);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(30, 90);
  for (std::size_t v = 0; v < voxels; ++v) {
    const Vec3d a = randomUnit(rng), b0 = randomUnit(rng);
    // b: at the chosen angle from a, in the plane of a and b0.
    const double ab = a.x * b0.x + a.y * b0.y + a.z * b0.z;
    Vec3d p{b0.x - ab * a.x, b0.y - ab * a.y, b0.z - ab * a.z};
    const double pl = std::sqrt(p.x * p.x + p.y * p.y + p.z * p.z);
    const double t = angle(rng) * M_PI / 180;
    const Vec3d b{std::cos(t) * a.x + std::sin(t) * p.x / pl, std::cos(t) * a.y + std::sin(t) * p.y / pl,
                  std::cos(t) * a.z + std::sin(t) * p.z / pl};
    for (const Vec3d& d : {a, b}) {
      const std::vector<double> y = evaluateShBasis(ShBasis::Tournier07, 8, d.x, d.y, d.z);
      for (int l = 0; l <= 8; l += 2)
        for (int m = -l; m <= l; ++m)
          f.coefficients[v * 45 + l * (l + 1) / 2 + m] += static_cast<float>(std::exp(-0.02 * l * (l + 1)) * y[l * (l + 1) / 2 + m]);
    }
  }
  return f;
}

// Each on the fixed 642 + 26 directions (`fixed`) and on the sampling
// adapted to each voxel (`caps`, defaultFodSampling: 162 + 26 directions
// and caps of the 642-direction icosphere around the maxima).
FodSampling samplingOf(const GridGeometry& g, bool caps) {
  return caps ? defaultFodSampling(g) : FodSampling{defaultFodSamplingDirections(g), {}};
}

void BM_FodUnitBallPerVoxel(benchmark::State& state, bool caps) {
  const FodField f = crossings(256);
  const FodCostSampler sampler(f, samplingOf(f.geometry, caps));
  FodUnitBall ball;
  std::size_t v = 0;
  for (auto _ : state) {
    sampler.unitBall(v, ball);
    benchmark::DoNotOptimize(ball.points.data());
    v = (v + 1) % 256;
  }
  state.counters["cpu_per_voxel"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                       benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK_CAPTURE(BM_FodUnitBallPerVoxel, fixed, false);
BENCHMARK_CAPTURE(BM_FodUnitBallPerVoxel, caps, true);

void BM_ConvexifiedNormAlong26NeighboursPerVoxel(benchmark::State& state, bool caps) {
  const FodField f = crossings(64);
  const FodCostSampler sampler(f, samplingOf(f.geometry, caps));
  const std::vector<Vec3d> queries = neighbourDirections26(f.geometry);
  for (auto _ : state) {
    const std::vector<float> table = convexifiedFodTable(sampler, queries);
    benchmark::DoNotOptimize(table.data());
  }
  state.counters["cpu_per_voxel"] = benchmark::Counter(static_cast<double>(state.iterations()) * 64,
                                                       benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK_CAPTURE(BM_ConvexifiedNormAlong26NeighboursPerVoxel, fixed, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_ConvexifiedNormAlong26NeighboursPerVoxel, caps, true)->Unit(benchmark::kMillisecond);

// The same voxels by the simple computation the tests hold the fast one to
// (FodCostSampler::unitBallReference, convexHullGauge per direction): the
// table's cost before it was made fast, in the same run.
void BM_FodUnitBallReferencePerVoxel(benchmark::State& state) {
  const FodField f = crossings(256);
  const FodCostSampler sampler(f, defaultFodSamplingDirections(f.geometry));
  FodUnitBall ball;
  std::size_t v = 0;
  for (auto _ : state) {
    sampler.unitBallReference(v, ball);
    benchmark::DoNotOptimize(ball.points.data());
    v = (v + 1) % 256;
  }
  state.counters["cpu_per_voxel"] = benchmark::Counter(static_cast<double>(state.iterations()),
                                                       benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_FodUnitBallReferencePerVoxel);

void BM_ConvexifiedNormReferencePerVoxel(benchmark::State& state) {
  const FodField f = crossings(64);
  const FodCostSampler sampler(f, defaultFodSamplingDirections(f.geometry));
  const std::vector<Vec3d> queries = neighbourDirections26(f.geometry);
  for (auto _ : state) {
    const std::vector<float> table = convexifiedFodNormsReference(sampler, queries);
    benchmark::DoNotOptimize(table.data());
  }
  state.counters["cpu_per_voxel"] = benchmark::Counter(static_cast<double>(state.iterations()) * 64,
                                                       benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
BENCHMARK(BM_ConvexifiedNormReferencePerVoxel)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
