// STVD and Lanthier's method on FOD metrics against exact answers (the
// tables of docs/fod.md, "STVD and Lanthier"):
//
//  norms     how far each way of measuring a segment vector on an FOD
//            metric lies above F*_exact, the convexified continuous norm
//            (the gauge of the hull of F's unit ball along 40962 icosphere
//            directions and the refined maxima), at 2000 random directions,
//            and its time per call (and experiments: the lattice helped by
//            the voxel's fibres; the lattice's min with F* tabulated on
//            caps around the maxima and on a band along the fibres' plane,
//            PatchModel and BandSegmentNorm), and the tables' cost per voxel;
//  constant  a constant FOD field of two crossing fibres (90, 60, 45, 30
//            degrees, in a plane tilted against the grid), whose distance
//            from the seed (the grid's centre) is F*_exact(x - s): mean,
//            p99, max relative error over all voxels, the voxels below
//            exact, and CPU seconds, per method and grid size;
//  curved    the bundle crossing of tests/itk/fod_propagation_test.cpp
//            (bundles that end, lobes that vary from voxel to voxel)
//            against Lanthier with M = 12.
//  sampling, constant-sampling   the samplings of "A sampling adapted to
//            each voxel" (named only);
//  constant-band   STVD on the constant crossings with today's segment norm
//            and with the band (BandSegmentNorm), errors and propagation
//            CPU seconds in one run (named only).
//
// Usage: stvd_fod_accuracy_table [norms|constant|curved|...]... (the first
// three when none is named). Tab-separated rows on stdout; CPU time of
// this process.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "fod_exact_norms.hpp"
#include "stvd/imaging/fod_cost.hpp"
#include "stvd/imaging/fod_metric.hpp"
#include "stvd/imaging/fod_segment_norm.hpp"
#include "stvd/propagation/propagation_definition.hpp"
#include "stvd/voxel_grid/stencil.hpp"
#include "stvd/voxel_grid/voxel_grid_domain.hpp"
#include "stvd/voxel_grid/voxel_grid_lanthier.hpp"
#include "stvd/voxel_grid/voxel_grid_propagation.hpp"

namespace {

using namespace stvd;
using namespace stvd::imaging;
using stvd::testing::ExactFodNorm;

double cpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

struct Summary {
  double mean = 0, p99 = 0, max = 0, min = 0;
  std::size_t below = 0, count = 0;
};

/// Relative errors; `below` counts those under -1e-5 (float rounding).
Summary summarise(std::vector<double> e) {
  Summary s;
  s.count = e.size();
  if (e.empty()) return s;
  for (double x : e) {
    s.mean += x;
    if (x < -1e-5) ++s.below;
  }
  s.mean /= static_cast<double>(e.size());
  std::sort(e.begin(), e.end());
  s.min = e.front();
  s.max = e.back();
  s.p99 = e[std::min(e.size() - 1, static_cast<std::size_t>(std::ceil(0.99 * static_cast<double>(e.size()))) - 1)];
  return s;
}

std::vector<Vec3d> randomDirections(int count) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n;
  std::vector<Vec3d> d;
  for (int i = 0; i < count; ++i) {
    Vec3d v{n(rng), n(rng), n(rng)};
    d.push_back((1.0 / std::sqrt(dot(v, v))) * v);
  }
  return d;
}

const double kAngles[] = {90, 60, 45, 30};

template <int Order>
void latticeRow(const char* name, double angle, const FodCostSampler& sampler, const std::vector<Vec3d>& dirs,
                const std::vector<double>& exact) {
  const auto metric = fodLatticeMetric<Order>(sampler);
  const auto& g = metric[0];
  std::vector<double> e;
  for (std::size_t i = 0; i < dirs.size(); ++i)
    e.push_back(LatticeTableNorm<Order>::length(g, float(dirs[i].x), float(dirs[i].y), float(dirs[i].z)) / exact[i] - 1);
  const double t0 = cpuSeconds();
  float sink = 0;
  const int repeats = 2000;
  for (int r = 0; r < repeats; ++r)
    for (const Vec3d& d : dirs) sink += LatticeTableNorm<Order>::length(g, float(d.x), float(d.y) + 1e-7f * r, float(d.z));
  const double ns = 1e9 * (cpuSeconds() - t0) / (repeats * double(dirs.size()));
  const Summary s = summarise(e);
  std::printf("norms\t%.0f\t%s\t%d\t%.4f\t%.4f\t%.4f\t%.5f\t%zu\t%.1f\t(%g)\n", angle, name, LatticeTableNorm<Order>::kCount,
              s.mean, s.p99, s.max, s.min, s.below, ns, double(sink) * 0);
}

/// An experiment for docs/fod.md, "STVD and Lanthier" (not in the library):
/// per voxel, F* tabulated along a few patches of directions, and the norm
/// N(v) = min(L(v), C(v)), L the order-2 lattice and C, for v in the cone
/// of a patch's triangle, the linear interpolation of the tabulated values
/// over that triangle: a triangle whose corners lie on the boundary of a
/// convex body lies inside it, so C >= F*, and so is the min (any
/// triangles of tabulated directions keep "never below"; their choice only
/// decides how much they help).
///
/// * A cap: each refined maximum p (one per antipodal pair) and rings of k
///   directions at a few degrees around it; the fan (p, q_1s, q_1s+1) of
///   the inner ring and each quad between two rings cut along both
///   diagonals. The first direction of each ring lies in the fibres' plane.
/// * A band along the fibres' plane: directions of the plane every `step`
///   degrees (and the maxima themselves) and the same azimuths at
///   elevations +-e_1, +-e_2, ... out of it; each quad cut both ways. The
///   plane: that of the first two maxima, or with one maximum that of p and
///   the point of F's ball farthest from p's axis (a crossing at 30 degrees
///   has one maximum: its lobes merge).
struct PatchModel {
  struct Triangle {
    float dual[9];  // rows: the barycentric coordinates' covectors
    float grad[3];  // the linear function of the values on the triangle's cone
  };
  struct Patch {
    bool cap;                       // a cap (cone around axis) or a band (around the plane normal to axis)
    float axis[3], e1[3], e2[3];
    float limit;                    // cap: cos of the outer ring; band: sin of the largest elevation
    std::vector<float> azimuth;     // the sectors' starts (radians, increasing from 0), per sector
    int perSector = 0;
    std::vector<Triangle> triangles;  // sector s: [s * perSector, (s + 1) * perSector)
  };
  std::vector<Patch> patches;
  int values = 0;  // F* values tabulated

  static Vec3d unit(Vec3d v) { return (1.0 / std::sqrt(dot(v, v))) * v; }
  static Vec3d cross(const Vec3d& a, const Vec3d& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  }
  static void put(float* f, const Vec3d& v) { f[0] = float(v.x), f[1] = float(v.y), f[2] = float(v.z); }
  static Triangle triangle(const Vec3d& x, double fx, const Vec3d& y, double fy, const Vec3d& z, double fz) {
    const Vec3d r0 = cross(y, z), r1 = cross(z, x), r2 = cross(x, y);
    const double det = dot(x, r0);
    const Vec3d rows[3] = {(1 / det) * r0, (1 / det) * r1, (1 / det) * r2};
    Triangle t;
    for (int i = 0; i < 3; ++i) put(t.dual + 3 * i, rows[i]);
    put(t.grad, fx * rows[0] + fy * rows[1] + fz * rows[2]);
    return t;
  }
  // Both triangulations of the quad (a0, a1 | b0, b1).
  static void quad(std::vector<Triangle>& t, const Vec3d& a0, double fa0, const Vec3d& a1, double fa1, const Vec3d& b0,
                   double fb0, const Vec3d& b1, double fb1) {
    t.push_back(triangle(a0, fa0, b0, fb0, b1, fb1));
    t.push_back(triangle(a0, fa0, b1, fb1, a1, fa1));
    t.push_back(triangle(a0, fa0, b0, fb0, a1, fa1));
    t.push_back(triangle(a1, fa1, b0, fb0, b1, fb1));
  }

  /// `value`: F* along a unit direction (the voxel's table). Empty
  /// `capRings` or `bandRows`: no caps, no band.
  template <class Value>
  PatchModel(const FodUnitBall& ball, const std::vector<double>& capRings, int k, double bandStep,
             const std::vector<double>& bandRows, Value&& value) {
    std::vector<Vec3d> axes;
    for (const Vec3d& p : ball.peaks) {
      bool known = false;
      for (const Vec3d& q : axes) known = known || std::abs(dot(p, q)) > 0.99;
      if (!known) axes.push_back(p);
    }
    if (axes.empty()) return;
    // The fibres' plane: spanned by axes[0] and `inPlane`.
    Vec3d inPlane{0, 0, 0};
    if (axes.size() > 1) {
      inPlane = axes[1] - dot(axes[1], axes[0]) * axes[0];
    } else {
      double far = -1;
      for (const Vec3d& w : ball.points) {
        const Vec3d o = w - dot(w, axes[0]) * axes[0];
        if (dot(o, o) > far) far = dot(o, o), inPlane = o;
      }
    }
    inPlane = unit(inPlane);
    const Vec3d normal = unit(cross(axes[0], inPlane));
    for (std::size_t a = 0; a < axes.size() && !capRings.empty(); ++a) {
      const Vec3d p = axes[a];
      // e1: in the fibres' plane, normal to p (the rings' first directions).
      Vec3d e1 = cross(normal - dot(normal, p) * p, p);
      if (dot(e1, e1) < 1e-8) e1 = std::abs(p.x) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0}, e1 = e1 - dot(e1, p) * p;
      e1 = unit(e1);
      const Vec3d e2 = cross(p, e1);
      Patch c;
      c.cap = true;
      put(c.axis, p), put(c.e1, e1), put(c.e2, e2);
      c.limit = float(std::cos(capRings.back() * M_PI / 180));
      for (int s = 0; s < k; ++s) c.azimuth.push_back(float(2 * M_PI * s / k));
      c.perSector = 1 + 4 * int(capRings.size() - 1);
      std::vector<std::vector<Vec3d>> ring;
      std::vector<std::vector<double>> f;
      for (double deg : capRings) {
        const double t = deg * M_PI / 180;
        ring.emplace_back(), f.emplace_back();
        for (int s = 0; s < k; ++s) {
          const double az = 2 * M_PI * s / k;
          ring.back().push_back(std::cos(t) * p + std::sin(t) * (std::cos(az) * e1 + std::sin(az) * e2));
          f.back().push_back(value(ring.back().back()));
          ++values;
        }
      }
      const double fp = value(p);
      ++values;
      for (int s = 0; s < k; ++s) {
        const int n = (s + 1) % k;
        c.triangles.push_back(triangle(p, fp, ring[0][s], f[0][s], ring[0][n], f[0][n]));
        for (std::size_t b = 0; b + 1 < ring.size(); ++b)
          quad(c.triangles, ring[b][s], f[b][s], ring[b][n], f[b][n], ring[b + 1][s], f[b + 1][s], ring[b + 1][n],
               f[b + 1][n]);
      }
      patches.push_back(std::move(c));
    }
    if (!bandRows.empty()) {
      Patch b;
      b.cap = false;
      const Vec3d e1 = axes[0], e2 = cross(normal, e1);  // azimuth 0 along the first maximum
      put(b.axis, normal), put(b.e1, e1), put(b.e2, e2);
      b.limit = float(std::sin(bandRows.back() * M_PI / 180));
      // Azimuths: every `bandStep` degrees over [0, 180) and the maxima's,
      // then the other half by symmetry (F*(-v) = F*(v)).
      std::vector<double> az;
      for (double t = 0; t < 180 - 1e-9; t += bandStep) az.push_back(t * M_PI / 180);
      for (const Vec3d& p : axes) {
        double t = std::atan2(dot(p, e2), dot(p, e1));
        if (t < 0) t += M_PI;
        if (t >= M_PI) t -= M_PI;
        if (std::abs(dot(p, normal)) < 0.2) az.push_back(t);
      }
      std::sort(az.begin(), az.end());
      std::vector<double> kept;
      for (double t : az)
        if (kept.empty() || t - kept.back() > 1e-3) kept.push_back(t);
      if (M_PI - kept.back() < 1e-3) kept.pop_back();
      const std::size_t half = kept.size();
      for (std::size_t i = 0; i < half; ++i) kept.push_back(kept[i] + M_PI);
      std::vector<double> rows = {0};
      for (double e : bandRows) rows.push_back(e), rows.insert(rows.begin(), -e);
      // Directions and values per (azimuth, row); the second half by symmetry.
      std::vector<std::vector<Vec3d>> dir(kept.size());
      std::vector<std::vector<double>> f(kept.size());
      for (std::size_t i = 0; i < kept.size(); ++i)
        for (double e : rows) {
          const double t = e * M_PI / 180;
          const Vec3d d = std::cos(t) * (std::cos(kept[i]) * e1 + std::sin(kept[i]) * e2) + std::sin(t) * normal;
          dir[i].push_back(d);
          if (i < half) {
            f[i].push_back(value(d));
            ++values;
          } else {
            f[i].push_back(f[i - half][rows.size() - 1 - f[i].size()]);  // -d: azimuth - pi, elevation -e
          }
        }
      b.perSector = 4 * int(rows.size() - 1);
      for (std::size_t i = 0; i < kept.size(); ++i) {
        b.azimuth.push_back(float(kept[i]));
        const std::size_t n = (i + 1) % kept.size();
        for (std::size_t r = 0; r + 1 < rows.size(); ++r)
          quad(b.triangles, dir[i][r], f[i][r], dir[n][r], f[n][r], dir[i][r + 1], f[i][r + 1], dir[n][r + 1],
               f[n][r + 1]);
      }
      patches.push_back(std::move(b));
    }
  }

  /// C(v): the least linear value over the patches' triangles whose cone
  /// holds v (or -v for caps), +infinity outside every patch.
  float operator()(float x, float y, float z) const {
    float best = std::numeric_limits<float>::infinity();
    const float n2 = x * x + y * y + z * z;
    for (const Patch& c : patches) {
      float h = c.axis[0] * x + c.axis[1] * y + c.axis[2] * z;
      float vx = x, vy = y, vz = z;
      if (c.cap) {
        const float sign = h < 0.f ? -1.f : 1.f;
        h *= sign;
        if (h <= 0.f || h * h < c.limit * c.limit * n2) continue;
        vx *= sign, vy *= sign, vz *= sign;
      } else if (h * h > c.limit * c.limit * n2 * 1.05f) {
        continue;
      }
      const float u = c.e1[0] * vx + c.e1[1] * vy + c.e1[2] * vz, w = c.e2[0] * vx + c.e2[1] * vy + c.e2[2] * vz;
      float az = std::atan2(w, u);
      if (az < 0.f) az += float(2 * M_PI);
      const int sectors = int(c.azimuth.size());
      int s = int(std::upper_bound(c.azimuth.begin(), c.azimuth.end(), az) - c.azimuth.begin()) - 1;
      s = s < 0 ? sectors - 1 : s;
      const Triangle* t = c.triangles.data() + s * c.perSector;
      for (int i = 0; i < c.perSector; ++i) {
        const float* d = t[i].dual;
        const float l0 = d[0] * vx + d[1] * vy + d[2] * vz, l1 = d[3] * vx + d[4] * vy + d[5] * vz,
                    l2 = d[6] * vx + d[7] * vy + d[8] * vz;
        // A vector on an edge shared by two triangles must not fall out of
        // both by rounding (the value would jump to L's): a tolerance of
        // float rounding, which moves the value by as little.
        const float tolerance = -1e-6f * (std::abs(vx) + std::abs(vy) + std::abs(vz));
        if (l0 < tolerance || l1 < tolerance || l2 < tolerance) continue;
        best = std::min(best, t[i].grad[0] * vx + t[i].grad[1] * vy + t[i].grad[2] * vz);
      }
    }
    return best;
  }
};

/// The band experiment as a segment norm STVD can run on (constant fields
/// only, in this bench): per voxel the order-2 lattice table and F* along a
/// fixed grid of directions around the fibres' plane (azimuths every 15
/// degrees from the first maximum, elevations 0, +-4, +-12, +-25 degrees:
/// 12 x 7 = 84 values, the other half of the circle by symmetry), and
/// N(v) = min(L(v), C(v)), C the linear interpolation over the grid's
/// triangles (each quad cut both ways). The parameters are interpolated
/// component by component as any grid norm's: exact for a constant field,
/// where every voxel holds the same; between voxels of different frames a
/// library version must combine the voxels' values N_j(v) instead.
struct BandSegmentNorm {
  static constexpr int kAzimuths = 12, kRows = 7, kSectors = 2 * kAzimuths;
  struct VertexParams {
    LatticeTableNorm<2>::VertexParams lattice;
    float frame[9];  // rows e1 (the first maximum), e2, n (the fibres' plane's normal)
    float band[kAzimuths * kRows];
  };
  using EdgeParams = VertexParams;
  static constexpr bool kEdgeRuleIsMean = true;
  // Interpolated between its nodes like the lattice table: STVD runs its
  // chain of edges alone on it, as on LatticeTableNorm (norms.hpp), so that
  // its figures compare with the table's.
  static constexpr bool kExactInEveryDirection = false;

  static double elevation(int r) {
    static const double deg[kRows] = {-25, -12, -4, 0, 4, 12, 25};
    return deg[r] * M_PI / 180;
  }
  /// The unit direction of grid node (sector a in [0, 24), row r) in the
  /// frame's coordinates, and the index of its value.
  static Vec3d node(int a, int r) {
    const double az = 2 * M_PI * a / kSectors, el = elevation(r);
    return {std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el)};
  }
  static int valueIndex(int a, int r) { return a < kAzimuths ? a * kRows + r : (a - kAzimuths) * kRows + (kRows - 1 - r); }

  struct Geometry {
    float dual[kSectors][kRows - 1][4][9];
    short corner[kSectors][kRows - 1][4][3];
    float sinRow[kRows];
  };
  static const Geometry& geometry() {
    static const Geometry g = [] {
      Geometry t{};
      for (int r = 0; r < kRows; ++r) t.sinRow[r] = float(std::sin(elevation(r)));
      const auto cross = [](const Vec3d& a, const Vec3d& b) {
        return Vec3d{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
      };
      for (int s = 0; s < kSectors; ++s)
        for (int r = 0; r + 1 < kRows; ++r) {
          const int n = (s + 1) % kSectors;
          const int tri[4][3][2] = {{{s, r}, {s, r + 1}, {n, r + 1}}, {{s, r}, {n, r + 1}, {n, r}},
                                    {{s, r}, {s, r + 1}, {n, r}}, {{n, r}, {s, r + 1}, {n, r + 1}}};
          for (int q = 0; q < 4; ++q) {
            const Vec3d x = node(tri[q][0][0], tri[q][0][1]), y = node(tri[q][1][0], tri[q][1][1]),
                        z = node(tri[q][2][0], tri[q][2][1]);
            const Vec3d r0 = cross(y, z), r1 = cross(z, x), r2 = cross(x, y);
            const double det = dot(x, r0);
            const Vec3d rows[3] = {(1 / det) * r0, (1 / det) * r1, (1 / det) * r2};
            for (int i = 0; i < 3; ++i) {
              t.dual[s][r][q][3 * i] = float(rows[i].x);
              t.dual[s][r][q][3 * i + 1] = float(rows[i].y);
              t.dual[s][r][q][3 * i + 2] = float(rows[i].z);
              t.corner[s][r][q][i] = short(valueIndex(tri[q][i][0], tri[q][i][1]));
            }
          }
        }
      return t;
    }();
    return g;
  }

  static EdgeParams edgeParams(const VertexParams& a, const VertexParams& b) {
    EdgeParams e;
    const float* pa = reinterpret_cast<const float*>(&a);
    const float* pb = reinterpret_cast<const float*>(&b);
    float* pe = reinterpret_cast<float*>(&e);
    for (std::size_t i = 0; i < sizeof(VertexParams) / sizeof(float); ++i) pe[i] = 0.5f * (pa[i] + pb[i]);
    return e;
  }

  /// C(v): the band's interpolation, +infinity outside the band.
  static float band(const VertexParams& g, float x, float y, float z) {
    const float* f = g.frame;
    const float u = f[0] * x + f[1] * y + f[2] * z, w = f[3] * x + f[4] * y + f[5] * z, h = f[6] * x + f[7] * y + f[8] * z;
    const float n2 = x * x + y * y + z * z;
    const Geometry& geo = geometry();
    const float top = geo.sinRow[kRows - 1];
    if (h * h > 1.1f * top * top * n2) return std::numeric_limits<float>::infinity();
    float az = std::atan2(w, u);
    if (az < 0.f) az += float(2 * M_PI);
    int s = int(az * float(kSectors / (2 * M_PI)));
    s = s < 0 ? 0 : (s >= kSectors ? kSectors - 1 : s);
    const float t = h / std::sqrt(n2);
    int r = 0;
    while (r < kRows - 2 && t > geo.sinRow[r + 1]) ++r;
    float best = std::numeric_limits<float>::infinity();
    const float tolerance = -1e-6f * (std::abs(u) + std::abs(w) + std::abs(h));
    for (int rr = std::max(r - 1, 0); rr <= std::min(r + 1, kRows - 2); ++rr)
      for (int q = 0; q < 4; ++q) {
        const float* d = geo.dual[s][rr][q];
        const float l0 = d[0] * u + d[1] * w + d[2] * h, l1 = d[3] * u + d[4] * w + d[5] * h,
                    l2 = d[6] * u + d[7] * w + d[8] * h;
        if (l0 < tolerance || l1 < tolerance || l2 < tolerance) continue;  // as PatchModel's
        const short* c = geo.corner[s][rr][q];
        best = std::min(best, l0 * g.band[c[0]] + l1 * g.band[c[1]] + l2 * g.band[c[2]]);
      }
    return best;
  }

  static float length(const EdgeParams& g, float x, float y, float z) {
    return std::min(LatticeTableNorm<2>::length(g.lattice, x, y, z), band(g, x, y, z));
  }
  static std::string invalidReason(const VertexParams& p) { return LatticeTableNorm<2>::invalidReason(p.lattice); }

  /// One voxel's parameters: `lattice` (fodLatticeMetric<2>), the frame from
  /// the ball's maxima (PatchModel's plane), F* along the grid by `value`.
  template <class Value>
  static VertexParams make(const LatticeTableNorm<2>::VertexParams& lattice, const FodUnitBall& ball, Value&& value) {
    VertexParams p{};
    p.lattice = lattice;
    std::vector<Vec3d> axes;
    for (const Vec3d& q : ball.peaks) {
      bool known = false;
      for (const Vec3d& o : axes) known = known || std::abs(dot(q, o)) > 0.99;
      if (!known) axes.push_back(q);
    }
    Vec3d e1{1, 0, 0}, inPlane{0, 1, 0};
    if (!axes.empty()) {
      e1 = axes[0];
      if (axes.size() > 1) {
        inPlane = axes[1] - dot(axes[1], e1) * e1;
      } else {
        double far = -1;
        for (const Vec3d& w : ball.points) {
          const Vec3d o = w - dot(w, e1) * e1;
          if (dot(o, o) > far) far = dot(o, o), inPlane = o;
        }
      }
    }
    const Vec3d e2 = PatchModel::unit(inPlane - dot(inPlane, e1) * e1), n = PatchModel::cross(e1, e2);
    const Vec3d frame[3] = {e1, e2, n};
    for (int i = 0; i < 3; ++i) PatchModel::put(p.frame + 3 * i, frame[i]);
    for (int a = 0; a < kAzimuths; ++a)
      for (int r = 0; r < kRows; ++r) {
        const Vec3d l = node(a, r);
        p.band[valueIndex(a, r)] = float(value(l.x * e1 + l.y * e2 + l.z * n));
      }
    return p;
  }
};

/// The cost of the rule a library version needs between voxels of
/// different frames, sum_j w_j N_j(v) over a sample's 8 voxels: the same
/// norm evaluated 8 times per sample (on a constant field, at 8 vectors
/// within float rounding of v, so that none is folded away), their mean.
struct BandSegmentNormEightCorners : BandSegmentNorm {
  static float length(const EdgeParams& g, float x, float y, float z) {
    float sum = 0.f;
    for (int n = 0; n < 8; ++n) {
      const float s = 1.f + 1e-7f * float(n);
      sum += BandSegmentNorm::length(g, s * x, y, z);
    }
    return 0.125f * sum;
  }
};

/// The patch models of PatchModel against today's order-2 lattice: per
/// configuration, the relative excess of min(L, C) over F*_exact, the time
/// per call, and the patches' F* values' time per voxel (by the voxel's
/// solver, reset as for a new voxel; the unit ball is today's).
void patchRows(double angle, const FodCostSampler& sampler, const FodUnitBall& ball, const std::vector<Vec3d>& dirs,
             const std::vector<double>& ex) {
  const auto metric = fodLatticeMetric<2>(sampler);
  const auto& g = metric[0];
  ConvexHullGauges gauge;
  gauge.reset(ball.points.data(), ball.points.size());
  struct Config {
    std::vector<double> rings;
    int k;
    double step;
    std::vector<double> rows;
  };
  const std::vector<Config> configs = {
      {{3}, 8, 0, {}},           {{12}, 8, 0, {}},           {{3, 12}, 8, 0, {}},
      {{}, 0, 10, {2, 5, 10}},   {{}, 0, 10, {4, 12}},       {{}, 0, 15, {4, 12, 25}},
      {{}, 0, 10, {4, 12, 25}},  {{}, 0, 15, {3, 8, 16, 30}}, {{}, 0, 20, {5, 15, 30}},
      {{}, 0, 15, {5, 15, 30}},  {{}, 0, 15, {6, 20}},        {{}, 0, 15, {8, 25}},
      {{3, 12}, 8, 15, {4, 12, 25}}, {{3, 8, 16}, 12, 5, {2, 5, 10, 20}},
  };
  for (const Config& config : configs) {
    const PatchModel model(ball, config.rings, config.k, config.step, config.rows, [&](const Vec3d& d) { return gauge(d); });
    std::vector<double> e;
    std::vector<std::pair<double, std::size_t>> worst;
    for (std::size_t i = 0; i < dirs.size(); ++i) {
      const float x = float(dirs[i].x), y = float(dirs[i].y), z = float(dirs[i].z);
      const double n = std::min(LatticeTableNorm<2>::length(g, x, y, z), model(x, y, z));
      e.push_back(n / ex[i] - 1);
      worst.push_back({e.back(), i});
    }
    const Summary s = summarise(e);
    double t0 = cpuSeconds();
    float sink = 0;
    const int repeats = 500;
    for (int r = 0; r < repeats; ++r)
      for (const Vec3d& d : dirs) {
        const float x = float(d.x), y = float(d.y) + 1e-7f * r, z = float(d.z);
        sink += std::min(LatticeTableNorm<2>::length(g, x, y, z), model(x, y, z));
      }
    const double ns = 1e9 * (cpuSeconds() - t0) / (repeats * double(dirs.size()));
    t0 = cpuSeconds();
    double sum = 0;
    const int voxels = 100;
    for (int r = 0; r < voxels; ++r) {
      gauge.reset(ball.points.data(), ball.points.size());
      const PatchModel again(ball, config.rings, config.k, config.step, config.rows, [&](const Vec3d& d) { return gauge(d); });
      sum += again.values;
    }
    const double us = 1e6 * (cpuSeconds() - t0) / voxels;
    gauge.reset(ball.points.data(), ball.points.size());
    std::string name = "lattice n=2";
    if (!config.rings.empty()) {
      name += " + caps";
      for (double r : config.rings) name += " " + std::to_string(int(r));
      name += " deg k=" + std::to_string(config.k);
    }
    if (!config.rows.empty()) {
      name += " + band step " + std::to_string(int(config.step)) + " rows";
      for (double r : config.rows) name += " " + std::to_string(int(r));
    }
    std::printf("norms\t%.0f\t%s\t49+%d\t%.4f\t%.4f\t%.4f\t%.5f\t%zu\t%.1f\t(%g)\ttable +%.1f us/voxel\n", angle,
                name.c_str(), model.values, s.mean, s.p99, s.max, s.min, s.below, ns, double(sink) * 0 + sum * 0, us);
    // Where the excess stays: the worst directions' angle to the nearest
    // maximum and out of the fibres' plane.
    std::sort(worst.rbegin(), worst.rend());
    const PatchModel::Patch* band = nullptr;
    for (const auto& p : model.patches)
      if (!p.cap) band = &p;
    for (int w = 0; w < 3 && band; ++w) {
      const Vec3d& d = dirs[worst[w].second];
      double nearest = 180;
      for (const Vec3d& p : ball.peaks) nearest = std::min(nearest, std::acos(std::min(1.0, dot(d, p))) * 180 / M_PI);
      const Vec3d nrm{band->axis[0], band->axis[1], band->axis[2]};
      std::printf("#   worst %.4f: %.1f deg from a maximum, %.1f deg out of the fibres' plane, exact %.3f\n",
                  worst[w].first, nearest, std::asin(std::abs(dot(d, nrm))) * 180 / M_PI, ex[worst[w].second]);
    }
  }
  {  // The band as STVD's segment norm (BandSegmentNorm): fixed azimuths, no maxima among its nodes.
    const BandSegmentNorm::VertexParams p = BandSegmentNorm::make(g, ball, [&](const Vec3d& d) { return gauge(d); });
    std::vector<double> e;
    for (std::size_t i = 0; i < dirs.size(); ++i)
      e.push_back(BandSegmentNorm::length(p, float(dirs[i].x), float(dirs[i].y), float(dirs[i].z)) / ex[i] - 1);
    const Summary s = summarise(e);
    double t0 = cpuSeconds();
    float sink = 0;
    const int repeats = 500;
    for (int r = 0; r < repeats; ++r)
      for (const Vec3d& d : dirs) sink += BandSegmentNorm::length(p, float(d.x), float(d.y) + 1e-7f * r, float(d.z));
    const double ns = 1e9 * (cpuSeconds() - t0) / (repeats * double(dirs.size()));
    t0 = cpuSeconds();
    const int voxels = 100;
    for (int r = 0; r < voxels; ++r) {
      gauge.reset(ball.points.data(), ball.points.size());
      sink += BandSegmentNorm::make(g, ball, [&](const Vec3d& d) { return gauge(d); }).band[0] * 0;
    }
    const double us = 1e6 * (cpuSeconds() - t0) / voxels;
    std::printf("norms\t%.0f\tBandSegmentNorm: lattice n=2 + band step 15 rows 4 12 25, fixed azimuths\t49+84\t%.4f\t%.4f\t%.4f\t%.5f\t%zu\t%.1f\t(%g)\ttable +%.1f us/voxel\n",
                angle, s.mean, s.p99, s.max, s.min, s.below, ns, double(sink) * 0, us);
  }
}

void norms() {
  std::printf("# norms: relative excess over F*_exact at 2000 random directions; ns per call\n");
  std::printf("table\tangle\tnorm\tvalues/voxel\tmean\tp99\tmax\tmin\tbelow\tns/call\n");
  const std::vector<Vec3d> dirs = randomDirections(2000);
  for (double angle : kAngles) {
    GridGeometry one;
    const FodField field = testing::constantCrossingField(one, angle);
    ExactFodNorm exact(field, 6);
    std::vector<double> ex;
    for (const Vec3d& d : dirs) ex.push_back(exact(d));
    const FodCostSampler sampler(field, defaultFodSamplingDirections(field.geometry));
    FodUnitBall ball;
    sampler.unitBall(0, ball);
    {  // F* of the 668 sampled points itself: the best any table of it can do.
      std::vector<double> e;
      for (std::size_t i = 0; i < dirs.size(); ++i)
        e.push_back(convexHullGauge(ball.points.data(), ball.points.size(), dirs[i]) / ex[i] - 1);
      const double t0 = cpuSeconds();
      double sink = 0;
      for (int r = 0; r < 5; ++r)
        for (const Vec3d& d : dirs) sink += convexHullGauge(ball.points.data(), ball.points.size(), d);
      const double ns = 1e9 * (cpuSeconds() - t0) / (5 * double(dirs.size()));
      const Summary s = summarise(e);
      std::printf("norms\t%.0f\tF* simplex (668+peaks)\t-\t%.4f\t%.4f\t%.4f\t%.5f\t%zu\t%.0f\t(%g)\n", angle, s.mean,
                  s.p99, s.max, s.min, s.below, ns, sink * 0);
    }
    {  // Today's: the gauge of the hull of the 26 tabulated points.
      const FodStencilMetric metric = fodStencilMetric(sampler);
      std::vector<double> e;
      for (std::size_t i = 0; i < dirs.size(); ++i)
        e.push_back(FodStencilNorm::length(metric[0], float(dirs[i].x), float(dirs[i].y), float(dirs[i].z)) / ex[i] - 1);
      const double t0 = cpuSeconds();
      float sink = 0;
      for (int r = 0; r < 20; ++r)
        for (const Vec3d& d : dirs) sink += FodStencilNorm::length(metric[0], float(d.x), float(d.y), float(d.z));
      const double ns = 1e9 * (cpuSeconds() - t0) / (20 * double(dirs.size()));
      const Summary s = summarise(e);
      std::printf("norms\t%.0f\thull of 26 (simplex)\t26\t%.4f\t%.4f\t%.4f\t%.5f\t%zu\t%.0f\t(%g)\n", angle, s.mean,
                  s.p99, s.max, s.min, s.below, ns, double(sink) * 0);
    }
    if (angle == 90) {  // The tables' cost: F* along each lattice's directions, per voxel (CPU).
      GridGeometry many;
      many.size = {200, 1, 1};
      const FodField field200 = testing::constantCrossingField(many, angle);
      const FodCostSampler s200(field200, defaultFodSamplingDirections(many));
      double t0 = cpuSeconds();
      (void)fodStencilMetric(s200);
      const double stencilUs = 1e6 * (cpuSeconds() - t0) / 200;
      t0 = cpuSeconds();
      (void)fodLatticeMetric<2>(s200);
      const double order2Us = 1e6 * (cpuSeconds() - t0) / 200;
      t0 = cpuSeconds();
      (void)fodLatticeMetric<3>(s200);
      const double order3Us = 1e6 * (cpuSeconds() - t0) / 200;
      std::printf("# table cost per voxel (us, CPU, unit ball included): 26 directions (13 programs) %.0f, "
                  "lattice n=2 (49) %.0f, n=3 (109) %.0f\n",
                  stencilUs, order2Us, order3Us);
    }
    {  // An experiment (not in the library): the order-2 lattice helped by the
       // voxel's fibres, |a| F*(p1) + |b| F*(p2) + L(v - a p1 - b p2) over
       // the projections of v on the peaks and on their plane, the least.
      const auto metric = fodLatticeMetric<2>(sampler);
      const auto& g = metric[0];
      std::vector<Vec3d> peaks;
      for (const Vec3d& p : ball.peaks) {
        bool known = false;
        for (const Vec3d& q : peaks) known = known || std::abs(dot(p, q)) > 0.99;
        if (!known) peaks.push_back(p);
      }
      std::vector<double> peakCost;
      for (const Vec3d& p : peaks) peakCost.push_back(convexHullGauge(ball.points.data(), ball.points.size(), p));
      const auto L = [&](const Vec3d& v) { return double(LatticeTableNorm<2>::length(g, float(v.x), float(v.y), float(v.z))); };
      std::vector<double> e;
      for (std::size_t i = 0; i < dirs.size(); ++i) {
        const Vec3d& v = dirs[i];
        double best = L(v);
        for (std::size_t k = 0; k < peaks.size(); ++k) {
          const double t = dot(v, peaks[k]);
          best = std::min(best, std::abs(t) * peakCost[k] + L(v - t * peaks[k]));
          for (std::size_t m = k + 1; m < peaks.size(); ++m) {
            // v's projection on the plane of the two peaks: a p_k + b p_m.
            const double c = dot(peaks[k], peaks[m]), vk = dot(v, peaks[k]), vm = dot(v, peaks[m]);
            const double det = 1 - c * c;
            if (det < 1e-6) continue;
            const double a = (vk - c * vm) / det, b = (vm - c * vk) / det;
            best = std::min(best, std::abs(a) * peakCost[k] + std::abs(b) * peakCost[m] +
                                      L(v - a * peaks[k] - b * peaks[m]));
          }
        }
        e.push_back(best / ex[i] - 1);
      }
      const Summary s = summarise(e);
      std::printf("norms\t%.0f\tlattice n=2 + fibres (experiment)\t49+\t%.4f\t%.4f\t%.4f\t%.5f\t%zu\t-\n", angle, s.mean,
                  s.p99, s.max, s.min, s.below);
    }
    latticeRow<1>("lattice n=1", angle, sampler, dirs, ex);
    latticeRow<2>("lattice n=2", angle, sampler, dirs, ex);
    latticeRow<3>("lattice n=3", angle, sampler, dirs, ex);
    patchRows(angle, sampler, ball, dirs, ex);
    std::fflush(stdout);
  }
}

struct Method {
  std::string name;
  int kind;  // 0 Dijkstra, 1 STVD, 2 Lanthier
  int parameter;
};

template <class Metric>
std::vector<double> run(const VoxelGridDomain& domain, const Metric& metric, VertexId seed, const Method& m,
                        double* seconds) {
  const double t0 = cpuSeconds();
  std::vector<double> d;
  if (m.kind == 2) {
    LanthierOptions o;
    o.steinerPoints = m.parameter;
    d = lanthierPropagate(domain, metric, {seed}, o).distance;
  } else {
    PropagationOptions o;
    o.method = m.kind == 0 ? stvd::Method::Dijkstra : stvd::Method::ShortTermVectorDijkstra;
    if (m.kind == 1) o.k = m.parameter;
    d = propagate(domain, metric, {seed}, o).distance;
  }
  *seconds = cpuSeconds() - t0;
  return d;
}

/// The samplings compared by `sampling` and `constant-sampling` (docs/fod.md,
/// "A sampling adapted to each voxel"): today's default and variants of a
/// coarse set with caps of a dense one around the maxima.
struct SamplingVariant {
  std::string name;
  int coarse, dense;  // icosphere levels; dense < 0: no caps
  double capDegrees;
  FodSampling of(const GridGeometry& g) const {
    if (dense < 0) return {defaultFodSamplingDirections(g, coarse), {}};
    return adaptiveFodSampling(g, coarse, dense, capDegrees);
  }
};

const std::vector<SamplingVariant>& samplingVariants() {
  static const std::vector<SamplingVariant> v = {
      {"L3 (642+26), no caps: the default before", 3, -1, 0},  {"L2 (162+26), no caps", 2, -1, 0},
      {"L2 + caps L3 r40", 2, 3, 40},  {"L2 + caps L3 r50 (the default)", 2, 3, 50}, {"L2 + caps L3 r60", 2, 3, 60},
      {"L2 + caps L4 r30", 2, 4, 30}, {"L2 + caps L4 r40", 2, 4, 40},
      {"L2 + caps L4 r50", 2, 4, 50},  {"L1 + caps L4 r40", 1, 4, 40}, {"L2 + caps L5 r40", 2, 5, 40},
  };
  return v;
}

/// One voxel of `fibres` (1 to 3) equal lobes: the first two as
/// crossingFibres(degrees), the third at `degrees` from the first out of
/// their plane.
FodField fibresField(const GridGeometry& g, int fibres, double degrees) {
  FodField f = testing::constantCrossingField(g, degrees);
  std::fill(f.coefficients.begin(), f.coefficients.end(), 0.f);
  Vec3d fibre[2];
  testing::crossingFibres(degrees, fibre);
  const Vec3d e1 = fibre[0];
  Vec3d nrm{e1.y * fibre[1].z - e1.z * fibre[1].y, e1.z * fibre[1].x - e1.x * fibre[1].z,
            e1.x * fibre[1].y - e1.y * fibre[1].x};
  nrm = (1.0 / std::sqrt(dot(nrm, nrm))) * nrm;
  const double t = degrees * M_PI / 180.0;
  const Vec3d third = std::cos(t) * e1 + std::sin(t) * nrm;
  float c[45] = {};
  testing::addFodLobe(f, c, fibre[0]);
  if (fibres >= 2) testing::addFodLobe(f, c, fibre[1]);
  if (fibres >= 3) testing::addFodLobe(f, c, third);
  for (std::size_t v = 0; v < g.voxelCount(); ++v) std::copy(c, c + 45, f.coefficients.data() + 45 * v);
  return f;
}

void sampling() {
  std::printf("# sampling: relative excess of F* over the converged F* (icosphere level 5, 10242 + 26 directions)\n");
  std::printf("# at 300 random directions and along the 26 and 98 table directions; one voxel per case\n");
  std::printf("table\tvariant\tfibres\tangle\tpoints\trandom mean\trandom max\t26 mean\t26 max\t98 mean\t98 max\tmin\n");
  GridGeometry one;
  const std::vector<Vec3d> dirs = randomDirections(300);
  const std::vector<Vec3d> q26 = neighbourDirections26(one);
  const std::vector<Vec3d> q98 = latticeVectors<2>(one);
  struct Case {
    int fibres;
    double angle;
    int lmax = 8;  // the lobes' degree: 4 gives broad lobes (their l > 4 coefficients zero)
  };
  std::vector<Case> cases = {{1, 90}};
  for (int fibres : {2, 3})
    for (double angle : kAngles) cases.push_back({fibres, angle});
  for (int fibres : {1, 2}) cases.push_back({fibres, 90, 4});
  cases.push_back({2, 60, 4});
  cases.push_back({2, 45, 4});
  const auto caseField = [](const GridGeometry& g, const Case& c) {
    FodField f = fibresField(g, c.fibres, c.angle);
    const int kept = (c.lmax + 1) * (c.lmax + 2) / 2;
    for (std::size_t v = 0; v < g.voxelCount(); ++v)
      std::fill(f.coefficients.begin() + 45 * v + kept, f.coefficients.begin() + 45 * (v + 1), 0.f);
    return f;
  };
  struct Exact {
    std::vector<double> random, n26, n98;
  };
  std::vector<Exact> exact;
  for (const Case& c : cases) {
    const FodField f = caseField(one, c);
    ExactFodNorm ex(f, 5);
    Exact e;
    for (const Vec3d& d : dirs) e.random.push_back(ex(d));
    for (const Vec3d& d : q26) e.n26.push_back(ex(d));
    for (const Vec3d& d : q98) e.n98.push_back(ex(d));
    exact.push_back(std::move(e));
  }
  for (const SamplingVariant& variant : samplingVariants()) {
    double worst[3] = {0, 0, 0}, lowest = 0, worstBroad = 0;  // worst: the lmax 8 cases
    for (std::size_t k = 0; k < cases.size(); ++k) {
      const FodField f = caseField(one, cases[k]);
      const FodCostSampler sampler(f, variant.of(one));
      FodUnitBall ball;
      sampler.unitBall(0, ball);
      ConvexHullGauges gauge;
      gauge.reset(ball.points.data(), ball.points.size());
      Summary s[3];
      const std::vector<Vec3d>* qs[3] = {&dirs, &q26, &q98};
      const std::vector<double>* es[3] = {&exact[k].random, &exact[k].n26, &exact[k].n98};
      double least = 0;
      for (int t = 0; t < 3; ++t) {
        std::vector<double> e;
        for (std::size_t i = 0; i < qs[t]->size(); ++i) e.push_back(gauge((*qs[t])[i]) / (*es[t])[i] - 1);
        s[t] = summarise(e);
        least = std::min(least, s[t].min);
        if (cases[k].lmax == 8)
          worst[t] = std::max(worst[t], s[t].max);
        else
          worstBroad = std::max(worstBroad, s[t].max);
      }
      lowest = std::min(lowest, least);
      std::printf("sampling\t%s\t%d\t%.0f%s\t%zu\t%.4f\t%.4f\t%.4f\t%.4f\t%.4f\t%.4f\t%.2g\n", variant.name.c_str(),
                  cases[k].fibres, cases[k].angle, cases[k].lmax == 8 ? "" : " (l<=4)", ball.points.size(), s[0].mean, s[0].max, s[1].mean, s[1].max,
                  s[2].mean, s[2].max, least);
    }
    // The tables' cost per voxel (CPU, unit ball included) on 256 voxels
    // of one to three fibres at random angles of 30 to 90 degrees.
    GridGeometry many;
    many.size = {256, 1, 1};
    FodField f = fibresField(many, 1, 90);
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> angle(30, 90);
    for (std::size_t v = 0; v < 256; ++v) {
      GridGeometry g1;
      const FodField fv = fibresField(g1, 1 + int(v % 3), angle(rng));
      std::copy(fv.coefficients.begin(), fv.coefficients.end(), f.coefficients.begin() + 45 * v);
    }
    const FodCostSampler sampler(f, variant.of(many));
    double t0 = cpuSeconds();
    for (int r = 0; r < 4; ++r) (void)convexifiedFodTable(sampler, q26);
    const double us26 = 1e6 * (cpuSeconds() - t0) / (4 * 256);
    t0 = cpuSeconds();
    for (int r = 0; r < 4; ++r) (void)convexifiedFodTable(sampler, q98);
    const double us98 = 1e6 * (cpuSeconds() - t0) / (4 * 256);
    FodUnitBall ball;
    t0 = cpuSeconds();
    std::size_t points = 0;
    for (int r = 0; r < 4; ++r)
      for (std::size_t v = 0; v < 256; ++v) sampler.unitBall(v, ball), points += ball.points.size();
    const double usBall = 1e6 * (cpuSeconds() - t0) / (4 * 256);
    std::printf("sampling-summary\t%s\tworst random %.4f\tworst 26 %.4f\tworst 98 %.4f\tmin %.2g\t"
                "unit ball %.1f us\ttable 26 %.1f us\ttable 98 %.1f us\tpoints %.0f\tworst broad lobes %.4f\n",
                variant.name.c_str(), worst[0], worst[1], worst[2], lowest, usBall, us26, us98,
                double(points) / (4 * 256), worstBroad);
    std::fflush(stdout);
  }
}

/// A constant crossing field at `angle` on an n^3 grid of 1 mm voxels,
/// seeded at its centre, with the exact distances F*_exact(x - s) of every
/// voxel (the scene of constant(), constantSampling() and constantBand()).
struct ConstantScene {
  ConstantScene(double angle, int n)
      : geometry(cube(n)), field(testing::constantCrossingField(GridGeometry{}, angle)),
        domain(geometry, Stencil::full26()), seed(domain.vertexAt(n / 2, n / 2, n / 2)),
        reference(geometry.voxelCount()) {
    ExactFodNorm exact(field, 6);
    const int c = n / 2;
    for (int k = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) reference[domain.vertexAt(i, j, k)] = exact.ofOffset(i - c, j - c, k - c);
  }
  static GridGeometry cube(int n) {
    GridGeometry g;
    g.size = {std::size_t(n), std::size_t(n), std::size_t(n)};
    return g;
  }
  /// The relative errors of `d` against the exact distances, the seed left out.
  Summary errorsOf(const std::vector<double>& d) const {
    std::vector<double> e;
    for (std::size_t v = 0; v < d.size(); ++v)
      if (v != seed) e.push_back(d[v] / reference[v] - 1);
    return summarise(e);
  }

  GridGeometry geometry;
  FodField field;
  VoxelGridDomain domain;
  VertexId seed;
  std::vector<double> reference;
};

/// Distances on the constant crossings under each sampling (Dijkstra and
/// STVD k = 6, 33^3, the default segment table).
void constantSampling() {
  std::printf("# constant-sampling: relative error against F*_exact(x - s), 33^3, per sampling\n");
  std::printf("table\tvariant\tangle\tmethod\tmean\tp99\tmax\tbelow exact\n");
  for (double angle : kAngles) {
    const int n = 33;
    const ConstantScene scene(angle, n);
    const GridGeometry& g = scene.geometry;
    const FodField& one = scene.field;
    const VoxelGridDomain& domain = scene.domain;
    const VertexId seed = scene.seed;
    for (const SamplingVariant& variant : samplingVariants()) {
      if (variant.dense < 0 ? variant.coarse != 3 : variant.coarse != 2 || variant.capDegrees != (variant.dense == 3 ? 50 : 40))
        continue;
      const FodCostSampler sampler(one, variant.of(g));
      const FodSegmentMetric segment = FodSegmentMetric::constant(g.voxelCount(), fodSegmentMetric(sampler)[0]);
      for (const Method& m : {Method{"dijkstra", 0, 0}, Method{"stvd k=6", 1, 6}}) {
        double seconds = 0;
        // Dijkstra's steps are neighbour steps, where the segment norm is
        // the 26-direction table (to 2e-6), as in constant().
        const std::vector<double> d = run(domain, segment, seed, m, &seconds);
        const Summary s = scene.errorsOf(d);
        std::printf("constant-sampling\t%s\t%.0f\t%s\t%.4f\t%.4f\t%.4f\t%zu\n", variant.name.c_str(), angle,
                    m.name.c_str(), s.mean, s.p99, s.max, s.below);
        std::fflush(stdout);
      }
    }
  }
}

void constant() {
  std::printf("# constant: relative error against F*_exact(x - s) over all voxels but the seed; CPU s\n");
  std::printf("table\tangle\tgrid\tmethod\tmean\tp99\tmax\tbelow exact\tvoxels\tcpu s\n");
  for (double angle : kAngles)
    for (int n : {17, 33}) {
      const ConstantScene scene(angle, n);
      const FodCostSampler sampler(scene.field, defaultFodSamplingDirections(scene.geometry));
      const FodSegmentMetric metric =
          FodSegmentMetric::constant(scene.geometry.voxelCount(), fodSegmentMetric(sampler)[0]);
      std::vector<Method> methods = {{"dijkstra", 0, 0}, {"stvd k=6", 1, 6}, {"stvd k=12", 1, 12},
                                     {"lanthier M=2", 2, 2}, {"lanthier M=4", 2, 4}};
      if (n <= 17) methods.push_back({"lanthier M=8", 2, 8});
      for (const Method& m : methods) {
        double seconds = 0;
        const std::vector<double> d = run(scene.domain, metric, scene.seed, m, &seconds);
        const Summary s = scene.errorsOf(d);
        std::printf("constant\t%.0f\t%d^3\t%s\t%.4f\t%.4f\t%.4f\t%zu\t%zu\t%.2f\n", angle, n, m.name.c_str(), s.mean,
                    s.p99, s.max, s.below, s.count, seconds);
        std::fflush(stdout);
      }
    }
}

/// STVD on the constant crossings with today's segment norm and with the
/// band (BandSegmentNorm), in one run: 33^3, the errors against
/// F*_exact(x - s) and the propagation's CPU seconds.
void constantBand() {
  std::printf("# constant-band: relative error against F*_exact(x - s), 33^3; CPU s of the propagation\n");
  std::printf("table\tangle\tnorm\tmethod\tmean\tp99\tmax\tbelow exact\tcpu s\n");
  for (double angle : kAngles) {
    const int n = 33;
    const ConstantScene scene(angle, n);
    const GridGeometry& g = scene.geometry;
    const FodField& one = scene.field;
    const VoxelGridDomain& domain = scene.domain;
    const VertexId seed = scene.seed;
    const FodCostSampler sampler(one, defaultFodSamplingDirections(GridGeometry{}));
    const FodSegmentMetric today = FodSegmentMetric::constant(g.voxelCount(), fodSegmentMetric(sampler)[0]);
    FodUnitBall ball;
    sampler.unitBall(0, ball);
    ConvexHullGauges gauge;
    gauge.reset(ball.points.data(), ball.points.size());
    const MetricField<BandSegmentNorm> band = MetricField<BandSegmentNorm>::constant(
        g.voxelCount(), BandSegmentNorm::make(today[0], ball, [&](const Vec3d& d) { return gauge(d); }));
    {  // The band's edge: segment vectors of STVD's chains (index offsets up
       // to 6) whose N moves by more than 1e-4 relative within float
       // rounding of themselves (N jumps from C to L where v leaves the band).
      int jumps = 0, vectors = 0;
      for (int k = -6; k <= 6; ++k)
        for (int j = -6; j <= 6; ++j)
          for (int i = -6; i <= 6; ++i) {
            if (i == 0 && j == 0 && k == 0) continue;
            ++vectors;
            const float x = float(i), y = float(j), z = float(k);
            const float a = BandSegmentNorm::length(band[0], x, y, z);
            for (int n = 1; n < 8; ++n)
              if (std::abs(BandSegmentNorm::length(band[0], (1.f + 1e-7f * float(n)) * x, y, z) / a - 1) > 1e-4f) {
                ++jumps;
                break;
              }
          }
      std::printf("# %.0f degrees: %d of %d index offsets up to 6 on the band's edge (N jumps within float rounding)\n",
                  angle, jumps, vectors);
    }
    const auto report = [&](const char* norm, const Method& m, const std::vector<double>& d, double seconds) {
      const Summary s = scene.errorsOf(d);
      std::printf("constant-band\t%.0f\t%s\t%s\t%.4f\t%.4f\t%.4f\t%zu\t%.2f\n", angle, norm, m.name.c_str(), s.mean,
                  s.p99, s.max, s.below, seconds);
      std::fflush(stdout);
    };
    for (const Method& m : {Method{"dijkstra", 0, 0}, Method{"stvd k=6", 1, 6}}) {
      double seconds = 0;
      std::vector<double> d = run(domain, today, seed, m, &seconds);
      report("lattice n=2 (today)", m, d, seconds);
      PropagationOptions o;  // run()'s options: the band has no Lanthier cells
      o.method = m.kind == 0 ? stvd::Method::Dijkstra : stvd::Method::ShortTermVectorDijkstra;
      if (m.kind == 1) o.k = m.parameter;
      const double t0 = cpuSeconds();
      d = propagate(domain, band, {seed}, o).distance;
      seconds = cpuSeconds() - t0;
      report("lattice n=2 + band (BandSegmentNorm)", m, d, seconds);
      if (m.kind == 1) {
        const MetricField<BandSegmentNormEightCorners> eight =
            MetricField<BandSegmentNormEightCorners>::constant(g.voxelCount(), band[0]);
        const double t1 = cpuSeconds();
        d = propagate(domain, eight, {seed}, o).distance;
        report("band, 8 evaluations per sample (the cost of the rule between voxels)", m, d, cpuSeconds() - t1);
      }
    }
  }
}

void curved() {
  std::printf("# curved: the bundle crossing (25 x 25 x 3, 5-voxel bundles) against Lanthier M = 12, voxels of the bundles\n");
  std::printf("table\tangle\tmethod\tmean\tp99\tmax\tmin\tbelow reference\tvoxels\tcpu s\n");
  for (double angle : {90.0, 45.0}) {
    constexpr int kN = 25, kC = 12;
    FodField f;
    f.geometry.size = {kN, kN, 3};
    f.lmax = 8;
    f.basis = ShBasis::Tournier07;
    f.frame = FodFrame::Scanner;
    f.lpsToShFrame = lpsToFodFrame(FodFrame::Scanner, f.geometry);
    f.coefficients.assign(f.geometry.voxelCount() * 45, 0.f);
    const Vec3d dir[2] = {{1, 0, 0}, {std::cos(angle * M_PI / 180), std::sin(angle * M_PI / 180), 0}};
    std::vector<std::uint8_t> inBundle(f.geometry.voxelCount(), 0);
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < kN; ++j)
        for (int i = 0; i < kN; ++i)
          for (int b = 0; b < 2; ++b) {
            const double x = i - kC, y = j - kC, along = x * dir[b].x + y * dir[b].y;
            if (std::hypot(x - along * dir[b].x, y - along * dir[b].y) <= 2 + 1e-9) {
              const std::size_t v = i + kN * (j + kN * k);
              testing::addFodLobe(f, f.coefficients.data() + 45 * v, dir[b]);
              inBundle[v] = 1;
            }
          }
    const FodCostSampler sampler(f, defaultFodSamplingDirections(f.geometry));
    const FodSegmentMetric metric = fodSegmentMetric(sampler, nullptr, 0);
    const VoxelGridDomain domain(f.geometry, Stencil::full26());
    const VertexId seed = domain.vertexAt(0, kC, 1);
    double seconds = 0;
    const std::vector<double> reference = run(domain, metric, seed, {"lanthier M=12", 2, 12}, &seconds);
    std::printf("curved\t%.0f\tlanthier M=12 (reference)\t-\t-\t-\t-\t-\t-\t%.2f\n", angle, seconds);
    for (const Method& m : std::vector<Method>{{"dijkstra", 0, 0}, {"stvd k=6", 1, 6}, {"stvd k=12", 1, 12},
                                               {"lanthier M=2", 2, 2}, {"lanthier M=4", 2, 4}, {"lanthier M=8", 2, 8}}) {
      const std::vector<double> d = run(domain, metric, seed, m, &seconds);
      std::vector<double> e;
      for (std::size_t v = 0; v < d.size(); ++v)
        if (v != seed && inBundle[v]) e.push_back(d[v] / reference[v] - 1);
      const Summary s = summarise(e);
      std::printf("curved\t%.0f\t%s\t%.4f\t%.4f\t%.4f\t%.4f\t%zu\t%zu\t%.2f\n", angle, m.name.c_str(), s.mean, s.p99,
                  s.max, s.min, s.below, s.count, seconds);
      std::fflush(stdout);
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  const auto wanted = [&](const char* name) {
    if (argc < 2) return true;
    for (int i = 1; i < argc; ++i)
      if (!std::strcmp(argv[i], name)) return true;
    return false;
  };
  if (wanted("norms")) norms();
  if (wanted("constant")) constant();
  if (wanted("curved")) curved();
  if (argc >= 2 && wanted("sampling")) sampling();
  if (argc >= 2 && wanted("constant-sampling")) constantSampling();
  if (argc >= 2 && wanted("constant-band")) constantBand();
}
