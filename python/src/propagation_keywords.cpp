#include "propagation_keywords.hpp"

#include <limits>

#include "bindings.hpp"
#include "stvd/system/memory.hpp"

namespace stvd::python {

PropagationChoice choiceOf(const std::optional<std::string>& method, const std::optional<int>& k,
                           const std::optional<std::string>& chainMeasure, const std::optional<std::string>& stencil,
                           const std::optional<int>& steiner, const std::optional<std::string>& domainConnectivity) {
  PropagationChoice choice;
  if (method) setMethod(choice, *method);
  if (steiner) setSteinerPoints(choice, *steiner);
  if (k) setMemoryDepth(choice, *k);
  if (chainMeasure) setChainMeasure(choice, *chainMeasure);
  if (stencil) setStencil(choice, *stencil);
  if (domainConnectivity) setDomainConnectivity(choice, *domainConnectivity);
  return choice;
}

double maxDistanceOf(const std::optional<double>& maxDistance) {
  if (!maxDistance) return std::numeric_limits<double>::infinity();
  if (!(*maxDistance > 0.0)) throw OptionError("--max-distance must be positive");
  return *maxDistance;
}

void checkMemory(const std::string& input, std::uint64_t neededBytes, const std::string& what, bool check) {
  if (!check) return;
  const std::optional<AvailableMemory> available = availableMemory();
  if (available && neededBytes > available->bytes)
    throw MemoryShortfallError(input + ": " + memoryShortfall(neededBytes, *available, what) +
                               "; pass memory_check=False to run anyway");
}

}  // namespace stvd::python
