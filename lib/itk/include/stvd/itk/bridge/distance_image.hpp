// Distances as an ITK image on the input's grid. Header-only; includes ITK.
#pragma once

#include <itkImage.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "stvd/errors.hpp"
#include "stvd/front_end/propagation_choice.hpp"

namespace stvd::imaging {

/// The image type of distance maps: float32, millimetres.
using ItkDistanceImage = itk::Image<float, 3>;

/// The value of a voxel no distance reached (outside the domain,
/// disconnected from the seeds, beyond a maximum distance) in a distance
/// image: -1, as `stvd distance` writes by default (kDefaultUnreachableValue;
/// a distance is never negative, so -1 cannot be mistaken for one). Pass
/// another (NaN, a large number) where a pipeline needs it.
inline constexpr float kItkUnreachableValue = static_cast<float>(kDefaultUnreachableValue);

/// Writes `distance` into the buffer of an allocated float image of as
/// many voxels, the way distanceImageFromDistances does.
inline void fillDistanceImage(const std::vector<double>& distance, ItkDistanceImage& image,
                              float unreachable = kItkUnreachableValue) {
  float* p = image.GetBufferPointer();
  for (std::size_t v = 0; v < distance.size(); ++v)
    p[v] = std::isfinite(distance[v]) ? static_cast<float>(distance[v]) : unreachable;
}

/// A distance image with the geometry of `reference` (origin, spacing,
/// direction; largest, buffered and requested regions all the reference's
/// buffered region, index included): voxel (i, j, k) of the grid
/// gridGeometryOf(reference) holds distance[i + nx (j + ny k)] as float32,
/// or `unreachable` where that distance is not finite. Throws
/// std::invalid_argument when the sizes differ.
template <class TReferenceImage>
ItkDistanceImage::Pointer distanceImageFromDistances(const std::vector<double>& distance,
                                                      const TReferenceImage& reference,
                                                      float unreachable = kItkUnreachableValue) {
  const auto region = reference.GetBufferedRegion();
  if (region.GetNumberOfPixels() != distance.size())
    throw std::invalid_argument("distance image: " + std::to_string(distance.size()) +
                                " distances for a region of " + std::to_string(region.GetNumberOfPixels()) +
                                " voxels");
  ItkDistanceImage::Pointer image = ItkDistanceImage::New();
  ItkDistanceImage::RegionType out;
  for (unsigned a = 0; a < 3; ++a) {
    out.SetIndex(a, region.GetIndex(a));
    out.SetSize(a, region.GetSize(a));
  }
  image->SetRegions(out);
  image->SetOrigin(reference.GetOrigin());
  image->SetSpacing(reference.GetSpacing());
  image->SetDirection(reference.GetDirection());
  image->Allocate();
  fillDistanceImage(distance, *image, unreachable);
  return image;
}

}  // namespace stvd::imaging
