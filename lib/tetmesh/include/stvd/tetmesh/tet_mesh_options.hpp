// Where the metric of a tetrahedral mesh comes from, as the front ends take
// it (--tensors, --tensor-attribute, --outside-image, --reference),
// declared once (stvd/front_end/option_declarations.hpp).
#pragma once

#include <vector>

#include "stvd/front_end/option_declarations.hpp"

namespace stvd::tetmesh {

/// The attribute where six tensor components per vertex or tetrahedron
/// start when none is stated.
inline constexpr int kDefaultFirstTensorAttribute = 0;

const std::vector<OptionDeclaration>& tetMeshOptionDeclarations();

}  // namespace stvd::tetmesh
