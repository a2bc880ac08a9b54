// The options of region connectivity as the front ends take them
// (--labels, --threads), declared once (stvd/front_end/option_declarations.hpp).
#pragma once

#include <vector>

#include "stvd/front_end/option_declarations.hpp"

namespace stvd {

const std::vector<OptionDeclaration>& regionConnectivityOptionDeclarations();

/// The threads asked for (0: one per core, threadCountFor).
unsigned regionThreadsOf(const OptionValues& values);

}  // namespace stvd
