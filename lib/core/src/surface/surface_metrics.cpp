#include "stvd/surface/surface_metrics.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace stvd {
namespace {

/// s1 a a^T + s2 b b^T + s3 n n^T for orthonormal a, b, n.
SymTensor3 fromFrame(Vec3d a, double s1, Vec3d b, double s2, Vec3d n, double s3) {
  auto entry = [&](double ai, double aj, double bi, double bj, double ni, double nj) {
    return static_cast<float>(s1 * ai * aj + s2 * bi * bj + s3 * ni * nj);
  };
  return {entry(a.x, a.x, b.x, b.x, n.x, n.x), entry(a.x, a.y, b.x, b.y, n.x, n.y),
          entry(a.x, a.z, b.x, b.z, n.x, n.z), entry(a.y, a.y, b.y, b.y, n.y, n.y),
          entry(a.y, a.z, b.y, b.z, n.y, n.z), entry(a.z, a.z, b.z, b.z, n.z, n.z)};
}

/// Eigen-decomposition of the symmetric 2x2 [[a, b], [b, c]]: values
/// l1 >= l2 and the unit eigenvector (cos t, sin t) of l1.
void eigen2(double a, double b, double c, double& l1, double& l2, double& t) {
  const double mean = 0.5 * (a + c), r = std::hypot(0.5 * (a - c), b);
  l1 = mean + r;
  l2 = mean - r;
  t = 0.5 * std::atan2(2.0 * b, a - c);
}

/// World tensor from a 2x2 {g11, g12, g22} in v's frame; checks positivity.
SymTensor3 fromLocal(const SurfaceDomain& s, VertexId v, double g11, double g12, double g22) {
  double l1, l2, t;
  eigen2(g11, g12, g22, l1, l2, t);
  if (!(l2 > 0.0) || !std::isfinite(l1))
    throw std::invalid_argument("metric at vertex " + std::to_string(v) +
                                ": the tangential tensor is not positive definite");
  const Vec3d n = s.normal(v), t1 = s.tangent(v), t2 = cross(n, t1);
  const Vec3d e1 = std::cos(t) * t1 + std::sin(t) * t2;
  const Vec3d e2 = cross(n, e1);
  return fromFrame(e1, l1, e2, l2, n, 0.5 * (l1 + l2));
}

}  // namespace

SymTensor3 tangentialPart(const SurfaceDomain& surface, VertexId v, const SymTensor3& g) {
  const Vec3d t1 = surface.tangent(v), t2 = cross(surface.normal(v), t1);
  const Vec3f a = toFloat(t1), b = toFloat(t2);
  const Vec3f ga = g.apply(a);
  return fromLocal(surface, v, dot(a, ga), dot(b, ga), g.quadraticForm(b));
}

RiemannianMetric isotropicSurfaceMetric(const SurfaceDomain& surface) {
  return RiemannianMetric::constant(surface.vertexCount(), SymTensor3{1, 0, 0, 1, 0, 1});
}

RiemannianMetric surfaceMetricFromWorldTensors(const SurfaceDomain& surface,
                                               const std::vector<SymTensor3>& tensors) {
  if (tensors.size() != surface.vertexCount())
    throw std::invalid_argument("there are " + std::to_string(tensors.size()) +
                                " tensors for " + std::to_string(surface.vertexCount()) +
                                " vertices");
  std::vector<SymTensor3> g(tensors.size());
  for (VertexId v = 0; v < surface.vertexCount(); ++v) g[v] = tangentialPart(surface, v, tensors[v]);
  return RiemannianMetric(std::move(g));
}

RiemannianMetric surfaceMetricFromFaceTensors(const SurfaceDomain& surface,
                                              const std::vector<SymTensor3>& faceTensors) {
  const PolygonList& faces = surface.faces();
  if (faceTensors.size() != faces.faceCount())
    throw std::invalid_argument("there are " + std::to_string(faceTensors.size()) +
                                " face tensors for " + std::to_string(faces.faceCount()) + " faces");
  std::vector<std::array<double, 6>> sum(surface.vertexCount(), std::array<double, 6>{});
  std::vector<double> weight(surface.vertexCount(), 0.0);
  for (std::size_t f = 0; f < faces.faceCount(); ++f) {
    const std::uint32_t b = faces.faceStart[f], e = faces.faceStart[f + 1];
    const SymTensor3& t = faceTensors[f];
    const double entries[6] = {t.xx, t.xy, t.xz, t.yy, t.yz, t.zz};
    for (std::uint32_t c = b; c < e; ++c) {
      const VertexId v = faces.faceVertex[c];
      const Vec3d p = surface.physicalPoint(v);
      const Vec3d a = surface.physicalPoint(faces.faceVertex[c + 1 < e ? c + 1 : b]) - p;
      const Vec3d q = surface.physicalPoint(faces.faceVertex[c > b ? c - 1 : e - 1]) - p;
      const double angle = std::atan2(norm(cross(a, q)), dot(a, q));
      for (int k = 0; k < 6; ++k) sum[v][k] += angle * entries[k];
      weight[v] += angle;
    }
  }
  std::vector<SymTensor3> g(surface.vertexCount());
  for (VertexId v = 0; v < surface.vertexCount(); ++v) {
    if (!(weight[v] > 0.0)) {
      g[v] = SymTensor3{1, 0, 0, 1, 0, 1};
      continue;
    }
    const auto& m = sum[v];
    const double w = weight[v];
    g[v] = tangentialPart(surface, v,
                          SymTensor3{float(m[0] / w), float(m[1] / w), float(m[2] / w),
                                     float(m[3] / w), float(m[4] / w), float(m[5] / w)});
  }
  return RiemannianMetric(std::move(g));
}

RiemannianMetric surfaceMetricFromLocalTensors(const SurfaceDomain& surface,
                                               const std::vector<std::array<double, 3>>& tensors) {
  if (tensors.size() != surface.vertexCount())
    throw std::invalid_argument("there are " + std::to_string(tensors.size()) +
                                " tensors for " + std::to_string(surface.vertexCount()) +
                                " vertices");
  std::vector<SymTensor3> g(tensors.size());
  for (VertexId v = 0; v < surface.vertexCount(); ++v)
    g[v] = fromLocal(surface, v, tensors[v][0], tensors[v][1], tensors[v][2]);
  return RiemannianMetric(std::move(g));
}

RiemannianMetric vectorFieldMetric(const SurfaceDomain& surface, const std::vector<Vec3d>& directions,
                                   double along, double across) {
  if (directions.size() != surface.vertexCount())
    throw std::invalid_argument("there are " + std::to_string(directions.size()) +
                                " directions for " + std::to_string(surface.vertexCount()) +
                                " vertices");
  if (!(along > 0.0) || !(across > 0.0) || !std::isfinite(along) || !std::isfinite(across))
    throw std::invalid_argument("the vector-field metric needs positive finite factors");
  std::vector<SymTensor3> g(directions.size());
  for (VertexId v = 0; v < surface.vertexCount(); ++v) {
    const Vec3d n = surface.normal(v), d = directions[v];
    if (!std::isfinite(d.x) || !std::isfinite(d.y) || !std::isfinite(d.z))
      throw std::invalid_argument("direction at vertex " + std::to_string(v) +
                                  " is not a finite vector");
    const Vec3d tangential = d - dot(d, n) * n;
    const double length = norm(tangential);
    if (length <= 1e-6 * norm(d) || length == 0.0) {
      g[v] = fromFrame(surface.tangent(v), along * along, cross(n, surface.tangent(v)),
                       along * along, n, along * along);
      continue;
    }
    const Vec3d e1 = (1.0 / length) * tangential, e2 = cross(n, e1);
    g[v] = fromFrame(e1, along * along, e2, across * across, n,
                     0.5 * (along * along + across * across));
  }
  return RiemannianMetric(std::move(g));
}

std::vector<PrincipalCurvature> principalCurvatures(const SurfaceDomain& surface) {
  const VertexId n = surface.vertexCount();
  // Second fundamental form per vertex as a world tensor (double, xx xy xz
  // yy yz zz), so that neighbours' estimates can be averaged.
  std::vector<std::array<double, 6>> form(n, std::array<double, 6>{});
  std::vector<std::uint8_t> fitted(n, 0);
  auto toWorld = [](Vec3d t1, Vec3d t2, double a, double b, double c) {
    auto e = [&](double p1, double p2, double q1, double q2) {
      return a * p1 * q1 + b * (p1 * q2 + p2 * q1) + c * p2 * q2;
    };
    return std::array<double, 6>{e(t1.x, t2.x, t1.x, t2.x), e(t1.x, t2.x, t1.y, t2.y),
                                 e(t1.x, t2.x, t1.z, t2.z), e(t1.y, t2.y, t1.y, t2.y),
                                 e(t1.y, t2.y, t1.z, t2.z), e(t1.z, t2.z, t1.z, t2.z)};
  };
  auto quadratic = [](const std::array<double, 6>& w, Vec3d p, Vec3d q) {
    return w[0] * p.x * q.x + w[3] * p.y * q.y + w[5] * p.z * q.z +
           w[1] * (p.x * q.y + p.y * q.x) + w[2] * (p.x * q.z + p.z * q.x) +
           w[4] * (p.y * q.z + p.z * q.y);
  };
  for (VertexId v = 0; v < n; ++v) {
    const Vec3d nv = surface.normal(v), t1 = surface.tangent(v), t2 = cross(nv, t1);
    // Normal equations of kappa(u) = a u1^2 + 2 b u1 u2 + c u2^2.
    double m[3][3] = {}, r[3] = {};
    for (std::uint32_t i = surface.ringBegin(v); i < surface.ringEnd(v); ++i) {
      const Vec3d d = surface.physicalPoint(surface.ringNeighbor(i)) - surface.physicalPoint(v);
      const double l2 = dot(d, d);
      const double u1 = dot(d, t1), u2 = dot(d, t2), ul = std::hypot(u1, u2);
      if (l2 <= 0.0 || ul <= 0.0) continue;
      const double kappa = 2.0 * dot(nv, d) / l2;
      const double row[3] = {(u1 / ul) * (u1 / ul), 2.0 * (u1 / ul) * (u2 / ul), (u2 / ul) * (u2 / ul)};
      for (int a = 0; a < 3; ++a) {
        r[a] += row[a] * kappa;
        for (int b = 0; b < 3; ++b) m[a][b] += row[a] * row[b];
      }
    }
    auto det3 = [](const double a[3][3]) {
      return a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) -
             a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0]) +
             a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    };
    const double trace = m[0][0] + m[1][1] + m[2][2];
    const double det = det3(m);
    // Too few distinct edge directions (e.g. a boundary vertex with three
    // neighbours, two of them opposite): the fit is left to the neighbours.
    if (!(trace > 0.0) || std::abs(det) < 1e-6 * trace * trace * trace) continue;
    double x[3];
    for (int c = 0; c < 3; ++c) {  // Cramer's rule
      double mc[3][3];
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) mc[a][b] = b == c ? r[a] : m[a][b];
      x[c] = det3(mc) / det;
    }
    form[v] = toWorld(t1, t2, x[0], x[1], x[2]);
    fitted[v] = 1;
  }
  std::vector<PrincipalCurvature> out(n);
  for (VertexId v = 0; v < n; ++v) {
    const Vec3d nv = surface.normal(v), t1 = surface.tangent(v), t2 = cross(nv, t1);
    std::array<double, 6> w = form[v];
    if (!fitted[v]) {  // mean of the fitted neighbours' forms
      int count = 0;
      for (std::uint32_t i = surface.ringBegin(v); i < surface.ringEnd(v); ++i) {
        const VertexId u = surface.ringNeighbor(i);
        if (!fitted[u]) continue;
        for (int c = 0; c < 6; ++c) w[c] += form[u][c];
        ++count;
      }
      for (int c = 0; c < 6; ++c) w[c] /= std::max(count, 1);
    }
    double l1, l2, t;
    eigen2(quadratic(w, t1, t1), quadratic(w, t1, t2), quadratic(w, t2, t2), l1, l2, t);
    const Vec3d e1 = std::cos(t) * t1 + std::sin(t) * t2, e2 = cross(nv, e1);
    PrincipalCurvature& pc = out[v];
    if (std::abs(l1) >= std::abs(l2)) {
      pc.kappaMax = l1, pc.directionMax = e1, pc.kappaMin = l2, pc.directionMin = e2;
    } else {
      pc.kappaMax = l2, pc.directionMax = e2, pc.kappaMin = l1, pc.directionMin = e1;
    }
  }
  return out;
}

RiemannianMetric curvatureMetric(const SurfaceDomain& surface, double gamma) {
  if (!(gamma >= 1.0) || !std::isfinite(gamma))
    throw std::invalid_argument("the curvature metric needs an anisotropy gamma >= 1");
  const std::vector<PrincipalCurvature> pc = principalCurvatures(surface);
  std::vector<SymTensor3> g(surface.vertexCount());
  for (VertexId v = 0; v < surface.vertexCount(); ++v) {
    const double kMax = std::abs(pc[v].kappaMax), kMin = std::abs(pc[v].kappaMin);
    const double ratio = kMax > 0.0 ? kMin / kMax : 1.0;
    const double across = 1.0 + (gamma - 1.0) * (1.0 - ratio);
    g[v] = fromFrame(pc[v].directionMin, 1.0, pc[v].directionMax, across * across,
                     surface.normal(v), 0.5 * (1.0 + across * across));
  }
  return RiemannianMetric(std::move(g));
}

}  // namespace stvd
