// Geodesic paths as ITK paths and back. Header-only; includes ITK.
#pragma once

#include <itkPolyLineParametricPath.h>

#include <vector>

#include "stvd/types.hpp"

namespace stvd::imaging {

/// What the vertices of an itk::PolyLineParametricPath<3> hold. ITK's own
/// path classes (PathIterator, PathToImageFilter) read them as continuous
/// indices of an image; ITK's MinimalPathExtraction fills them with
/// physical points instead. Say which.
enum class ItkPathCoordinates {
  ContinuousIndex,  ///< continuous indices of the reference image (its index space, region offset included)
  Physical,         ///< physical points in LPS millimetres (as MinimalPathExtraction's paths)
};

using ItkPath = itk::PolyLineParametricPath<3>;

/// A path of physical points (LPS millimetres, as stvd's TracedPath::points:
/// from the source end to the target) as an ITK path whose vertices are in
/// `coordinates` of `reference`.
template <class TReferenceImage>
ItkPath::Pointer itkPathFromPoints(const std::vector<Vec3d>& points, const TReferenceImage& reference,
                                   ItkPathCoordinates coordinates) {
  ItkPath::Pointer path = ItkPath::New();
  for (const Vec3d& x : points) {
    typename TReferenceImage::PointType p;
    p[0] = x.x, p[1] = x.y, p[2] = x.z;
    ItkPath::ContinuousIndexType vertex;
    if (coordinates == ItkPathCoordinates::ContinuousIndex) {
      reference.TransformPhysicalPointToContinuousIndex(p, vertex);
    } else {
      for (unsigned a = 0; a < 3; ++a) vertex[a] = p[a];
    }
    path->AddVertex(vertex);
  }
  return path;
}

/// The physical points (LPS millimetres) of an ITK path whose vertices are
/// in `coordinates` of `reference`: the inverse of itkPathFromPoints.
template <class TReferenceImage>
std::vector<Vec3d> pointsFromItkPath(const ItkPath& path, const TReferenceImage& reference,
                                     ItkPathCoordinates coordinates) {
  std::vector<Vec3d> points;
  const auto* vertices = path.GetVertexList();
  points.reserve(vertices->Size());
  for (unsigned n = 0; n < vertices->Size(); ++n) {
    const ItkPath::ContinuousIndexType& vertex = vertices->ElementAt(n);
    typename TReferenceImage::PointType p;
    if (coordinates == ItkPathCoordinates::ContinuousIndex) {
      reference.TransformContinuousIndexToPhysicalPoint(vertex, p);
    } else {
      for (unsigned a = 0; a < 3; ++a) p[a] = vertex[a];
    }
    points.push_back({p[0], p[1], p[2]});
  }
  return points;
}

}  // namespace stvd::imaging
