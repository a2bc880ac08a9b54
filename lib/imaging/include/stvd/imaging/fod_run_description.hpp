// How an FOD run's metric is described in its statistics (the tool's
// --stats "fod_norm") and on its QC page, in one place for the tool and the
// Python package, whose pages of the same run must say the same.
#pragma once

#include <string>

namespace stvd::imaging {

/// "convexified F* along the lattice directions of order 2 (49 per voxel),
/// interpolated" for the segment norm (STVD, Lanthier), "convexified F*
/// along the 26 neighbour directions" for Dijkstra's table.
std::string fodNormDescription(bool segments);

}  // namespace stvd::imaging
