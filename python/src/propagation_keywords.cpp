#include "propagation_keywords.hpp"

#include <limits>
#include <stdexcept>

#include "bindings.hpp"
#include "stvd/front_end/mesh_options.hpp"
#include "stvd/front_end/path_tracing_options.hpp"
#include "stvd/front_end/propagation_choice_options.hpp"
#include "stvd/front_end/region_connectivity_options.hpp"
#include "stvd/imaging/fod_input_options.hpp"
#include "stvd/imaging/seed_options.hpp"
#include "stvd/imaging/tensor_input_options.hpp"
#include "stvd/system/memory.hpp"
#include "stvd/tetmesh/tet_mesh_options.hpp"

namespace stvd::python {

PropagationChoice choiceOf(const std::optional<std::string>& method, const std::optional<int>& k,
                           const std::optional<std::string>& chainMeasure, const std::optional<std::string>& stencil,
                           const std::optional<int>& steiner, const std::optional<std::string>& domainConnectivity) {
  // Checked by the options' declarations, with messages in keyword names.
  OptionValues values(OptionNaming::Keywords);
  if (method) values.set(propagationOption("--method"), *method);
  if (steiner) values.set(propagationOption("--steiner"), static_cast<long long>(*steiner));
  if (k) values.set(propagationOption("--k"), static_cast<long long>(*k));
  if (chainMeasure) values.set(propagationOption("--chain-measure"), *chainMeasure);
  if (stencil) values.set(propagationOption("--stencil"), *stencil);
  if (domainConnectivity) values.set(propagationOption("--domain-connectivity"), *domainConnectivity);
  return propagationChoiceOf(values);
}

double maxDistanceOf(const std::optional<double>& maxDistance) {
  if (!maxDistance) return std::numeric_limits<double>::infinity();
  OptionValues values(OptionNaming::Keywords);
  values.set(propagationOption("--max-distance"), *maxDistance);
  return *values.number("--max-distance");
}

const std::vector<OptionDeclaration>& optionDeclarations() {
  static const std::vector<OptionDeclaration> all = [] {
    std::vector<OptionDeclaration> all;
    for (const auto* table : {&imaging::seedOptionDeclarations(), &meshOptionDeclarations(),
                              &regionConnectivityOptionDeclarations(), &propagationOptionDeclarations(),
                              &imaging::tensorInputOptionDeclarations(), &tetmesh::tetMeshOptionDeclarations(),
                              &pathTracingOptionDeclarations(), &imaging::fodInputOptionDeclarations()})
      all.insert(all.end(), table->begin(), table->end());
    return all;
  }();
  return all;
}

std::string keywordOf(const std::string& flag) {
  const OptionDeclaration* option = findOption(optionDeclarations(), flag);
  if (!option) throw std::logic_error("no option " + flag);
  return option->keyword;
}

void checkMemory(const std::string& input, std::uint64_t neededBytes, const std::string& what, bool check) {
  if (!check) return;
  const std::optional<AvailableMemory> available = availableMemory();
  if (available && neededBytes > available->bytes)
    throw MemoryShortfallError(input + ": " + memoryShortfall(neededBytes, *available, what) +
                               "; pass " +
                               optionSwitchedOn(propagationOption("--no-memory-check"), OptionNaming::Keywords) +
                               " to run anyway");
}

}  // namespace stvd::python
