// What a stored value means as a label, whatever it comes from: the rules of
// readLabelImage (stvd/itk/scalar_image_io.hpp), shared by the ITK path, the MRtrix
// reader and label arrays in memory (the Python package's).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "stvd/voxel_grid/grid_geometry.hpp"

namespace stvd::imaging {

/// The label of an unsigned 64-bit value; a value beyond 2^63 - 1 throws
/// ImageIoError naming `name` and voxel number `v` of `g`.
std::int64_t labelOfUnsigned64(std::uint64_t value, const std::string& name, const GridGeometry& g, std::size_t v);

/// The label of a floating-point value: NaN is 0 (no label), an integer of
/// magnitude at most 2^53 is itself; any other value throws ImageIoError
/// naming `name`, the voxel and the value.
std::int64_t labelOfReal(double x, const std::string& name, const GridGeometry& g, std::size_t v);

}  // namespace stvd::imaging
