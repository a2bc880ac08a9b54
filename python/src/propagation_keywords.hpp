// The propagation keywords every Python call shares (method, k,
// chain_measure, stencil, domain_connectivity, steiner, max_distance,
// memory_check), checked by the options' declarations
// (stvd/front_end/propagation_choice_options.hpp), so that values, defaults and
// messages are the tool's, with the keywords' names.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "stvd/front_end/propagation_choice.hpp"

namespace stvd::python {

/// The choice from the keywords; None keeps the library's default (k: the
/// default of the kind of domain the choice runs on).
PropagationChoice choiceOf(const std::optional<std::string>& method, const std::optional<int>& k,
                           const std::optional<std::string>& chainMeasure, const std::optional<std::string>& stencil,
                           const std::optional<int>& steiner,
                           const std::optional<std::string>& domainConnectivity = std::nullopt);

/// max_distance: infinity for None; OptionError unless positive.
double maxDistanceOf(const std::optional<double>& maxDistance);

/// Every option the library declares (the tool adds its own outputs), for
/// stvd.defaults and the package's checks.
const std::vector<OptionDeclaration>& optionDeclarations();

/// The keyword of the option with the tool's flag `flag` ("--seed-voxel":
/// "seeds"), for the package's messages.
std::string keywordOf(const std::string& flag);

/// memory_check: the tool's memory check, before a run's large
/// allocations. MemoryShortfallError (MemoryError) naming `input` when the
/// run still needs more than the memory available (the system's, the
/// control group's, the address-space limit's), unless `check` is false
/// (memory_check=False, the tool's --no-memory-check). Nothing is refused
/// when that is unknown.
void checkMemory(const std::string& input, std::uint64_t neededBytes, const std::string& what, bool check);

}  // namespace stvd::python
