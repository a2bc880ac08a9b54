// Metrics on a surface (paper, section 3): per-vertex tensors in tangent
// planes, built from isotropic, world-space, local 2x2, curvature and
// direction-field input. See docs/surfaces.md.
#pragma once

#include <array>
#include <vector>

#include "stvd/metric/metric_field.hpp"
#include "stvd/surface/surface_domain.hpp"
#include "stvd/types.hpp"

namespace stvd {

/// A surface metric is a RiemannianMetric over a SurfaceDomain holding, per
/// vertex, a world-space tensor whose restriction to the vertex's tangent
/// plane is the metric there. Only the tangential part matters; the builders
/// below fill the normal direction with the mean of the two tangential
/// eigenvalues so that the stored 3x3 tensor is positive definite and an
/// edge frame slightly off the tangent plane sees a neutral value.

/// G_world = P G P + (tr(P G P) / 2) n n^T with P = I - n n^T: the tangential
/// part of a 3D tensor at v.
SymTensor3 tangentialPart(const SurfaceDomain& surface, VertexId v, const SymTensor3& g);

/// The identity: surface (geodesic) distance.
RiemannianMetric isotropicSurfaceMetric(const SurfaceDomain& surface);

/// 3D tensors (xx, xy, xz, yy, yz, zz, world frame) projected to the
/// tangent planes. Throws std::invalid_argument naming the vertex whose
/// tangential part is not positive definite, or for a size mismatch.
RiemannianMetric surfaceMetricFromWorldTensors(const SurfaceDomain& surface,
                                               const std::vector<SymTensor3>& tensors);

/// 3D tensors per face (world frame, faces in input order), averaged to the
/// vertices weighted by the faces' corner angles and then projected to the
/// tangent planes: the paper's "approximate one form from another via
/// averaging" (section 3). A vertex in no face gets the identity. Throws like
/// surfaceMetricFromWorldTensors.
RiemannianMetric surfaceMetricFromFaceTensors(const SurfaceDomain& surface,
                                              const std::vector<SymTensor3>& faceTensors);

/// 2x2 tensors {g11, g12, g22} in each vertex's frame (t1, t2 = n x t1,
/// SurfaceDomain::tangent). Throws like surfaceMetricFromWorldTensors.
RiemannianMetric surfaceMetricFromLocalTensors(const SurfaceDomain& surface,
                                               const std::vector<std::array<double, 3>>& tensors);

/// Vector-field metric: at each vertex the direction d (world vector,
/// projected to the tangent plane and normalised) and G = along^2 d d^T +
/// across^2 (n x d)(n x d)^T, i.e. a unit step along the field costs `along`
/// and across it `across` (the tensor's eigenvalues are along^2, across^2).
/// A vertex whose direction is (nearly) normal or zero gets the isotropic
/// tensor along^2 I. Throws std::invalid_argument for a size mismatch or a
/// non-positive factor.
RiemannianMetric vectorFieldMetric(const SurfaceDomain& surface, const std::vector<Vec3d>& directions,
                                   double along, double across);

/// Principal curvatures and directions per vertex, estimated from the
/// normal curvatures of the 1-ring edges (kappa = 2 n.(x_w - x_v)/|x_w - x_v|^2)
/// by a least-squares fit of the second fundamental form in v's frame.
struct PrincipalCurvature {
  double kappaMin = 0.0, kappaMax = 0.0;  // |kappaMin| <= |kappaMax|
  Vec3d directionMin, directionMax;       // unit, tangent, orthogonal
};
std::vector<PrincipalCurvature> principalCurvatures(const SurfaceDomain& surface);

/// Curvature tensor metric with anisotropy gamma >= 1: eigenvectors along the
/// principal directions; a unit step along the direction of smaller
/// |curvature| costs 1 and along the other 1 + (gamma - 1)(1 - |kmin|/|kmax|).
/// So where one principal curvature vanishes (a cylinder, a ridge) the local
/// anisotropy is gamma, at umbilics (sphere, plane) the metric is isotropic,
/// and geodesics prefer to run along lines of small curvature. gamma = 1 is
/// the isotropic metric.
RiemannianMetric curvatureMetric(const SurfaceDomain& surface, double gamma);

}  // namespace stvd
