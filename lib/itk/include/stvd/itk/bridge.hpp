// The ITK bridge: stvd inside an ITK pipeline, header-only. Tensor images
// with their frame stated (bridge/tensor_image.hpp), distance maps as ITK
// images (bridge/distance_image.hpp), paths as ITK paths
// (bridge/path.hpp) and the filter GeodesicDistanceImageFilter with ITK's
// progress and abort (bridge/geodesic_distance_image_filter.hpp).
//
// Unlike stvd/itk.hpp, these headers include ITK's: a consumer finds ITK
// itself (find_package(ITK), include(${ITK_USE_FILE})) and links
// ${ITK_LIBRARIES} with stvd::itk. docs/library.md shows the whole program.
#pragma once

#include "stvd/itk/bridge/distance_image.hpp"
#include "stvd/itk/bridge/geodesic_distance_image_filter.hpp"
#include "stvd/itk/bridge/path.hpp"
#include "stvd/itk/bridge/tensor_image.hpp"
