// How the file readers report their progress (shared by the imaging adapter
// and the ITK file I/O, and no one else): one operation per read, its steps
// the file's values; what a library call does in one piece (ITK's read, the
// bytes of an MRtrix file) counts as done when it returns, and what we loop
// over ourselves (decoding MRtrix values, converting components into
// tensors, values into labels) reports as it goes.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "stvd/imaging/mrtrix_image.hpp"
#include "stvd/imaging/tensor_arrays.hpp"
#include "stvd/system/interrupter.hpp"
#include "stvd/types.hpp"

namespace stvd::imaging::detail {

/// readMrtrixImage reporting to `progress`: the scope's total becomes 2 x
/// the file's values + `stepsAfter` once the header is read; the bytes are
/// the first half (done when read), the decoding the second (a step per
/// value).
MrtrixImage readMrtrixImage(const std::string& path, InterruptScope& progress, std::uint64_t stepsAfter = 0);
/// readMrtrixLabelImage the same way.
MrtrixLabelImage readMrtrixLabelImage(const std::string& path, InterruptScope& progress);

/// tensorsFromArray with a step of `progress` per voxel, numbered from
/// `from`.
template <class T>
std::vector<SymTensor3> tensorsFromArray(const T* components, const std::array<std::size_t, 3>& size,
                                         const TensorComponentLayout& layout, const Matrix3& frameChange,
                                         InterruptScope& progress, std::uint64_t from);

}  // namespace stvd::imaging::detail
