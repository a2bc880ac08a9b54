// The options of path tracing as the front ends take them (--step,
// --smooth, --no-refine, --discrete), declared once
// (stvd/front_end/option_declarations.hpp) with the defaults of PathTracingOptions.
#pragma once

#include <vector>

#include "stvd/front_end/option_declarations.hpp"
#include "stvd/voxel_grid/path_tracing.hpp"

namespace stvd {

const std::vector<OptionDeclaration>& pathTracingOptionDeclarations();

/// The tracing options the given options make (defaults for the others);
/// --discrete, which chooses discreteGeodesicPath instead, is the front
/// end's to read.
PathTracingOptions pathTracingOptionsOf(const OptionValues& values);

}  // namespace stvd
