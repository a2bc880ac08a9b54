// The propagation's options as the front ends take them (--method,
// --steiner, --k, --chain-measure, --stencil, --domain-connectivity,
// --max-distance, --no-memory-check, --unreachable-value), declared once
// (stvd/front_end/option_declarations.hpp) with the library's defaults: the method of
// a default PropagationChoice, per kind of domain defaultMemoryDepth,
// kDefaultChainMeasure, kMaxMemoryDepth, kMaxSteinerPoints,
// kDefaultUnreachableValue.
#pragma once

#include <vector>

#include "stvd/front_end/option_declarations.hpp"
#include "stvd/front_end/propagation_choice.hpp"

namespace stvd {

/// The declarations of the propagation's options.
const std::vector<OptionDeclaration>& propagationOptionDeclarations();
/// The one among them with this flag (std::logic_error when there is none).
const OptionDeclaration& propagationOption(const std::string& flag);

/// Sets the option `flag` of `choice` to `value`, which its declaration
/// has checked (what propagationChoiceOf does for each given option).
void applyPropagationOption(PropagationChoice& choice, const std::string& flag, const OptionValue& value);

/// The choice the given options make (defaults for the others); its
/// messages will be in the values' naming. The values were checked when
/// they were set; combinations are checked by checkPropagationChoice.
PropagationChoice propagationChoiceOf(const OptionValues& values);

}  // namespace stvd
