// The options of distances over meshes as the front ends take them: seed
// vertices and points on surfaces and tetrahedral meshes (--seed-vertex,
// --seed-at) and the surface metric (--metric, --anisotropy,
// stvd/surface/surface_metrics.hpp), declared once (stvd/front_end/option_declarations.hpp).
#pragma once

#include <string>
#include <vector>

#include "stvd/front_end/option_declarations.hpp"

namespace stvd {

const std::vector<OptionDeclaration>& meshOptionDeclarations();

/// OptionError, naming options as `naming` says, for a surface metric and
/// anisotropy that do not go together: curvature and field metrics need
/// an anisotropy, the others take none. `metric` is the --metric value
/// ("field:FILE") or the keyword's ("field").
void checkSurfaceMetricChoice(const std::string& metric, bool anisotropyGiven, OptionNaming naming);

}  // namespace stvd
