// Before the large allocations of a run: does the rest of it fit into the
// memory the machine (its control group, its address-space limit) has
// available? A run that cannot fit is refused in one line instead of being
// killed by the kernel, or failing, after minutes of work.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "stvd/system/memory.hpp"

namespace stvd::tool {

/// The check made for one run, for reports (--stats).
struct MemoryCheck {
  /// What the rest of the run allocates (the propagation's state and
  /// result, the Steiner graph, the outputs): a function of the sizes only.
  std::uint64_t neededBytes = 0;
  /// Resident when the check was made (everything read so far); the run's
  /// estimated peak is residentBytes + neededBytes.
  std::uint64_t residentBytes = 0;
  std::optional<AvailableMemory> available;
  bool skipped = false;  // --no-memory-check
};

/// Compares `neededBytes`, what the rest of the run will allocate (`what`
/// says for what: "STVD on 401,408 voxels"), with the available memory.
/// Throws ToolError(kExitMemory) naming `input` when it is more, unless
/// `skip`. Nothing is refused when the available memory is unknown.
MemoryCheck checkMemory(const std::string& input, std::uint64_t neededBytes, const std::string& what, bool skip);

/// Bytes per voxel the distance map costs once computed: the float values,
/// the statistics' copy of the finite distances, and what writing and
/// checking the file takes.
constexpr std::uint64_t kOutputBytesPerVoxel = 24;

/// The check as the JSON object of --stats: {"needed_bytes": ..., "check": "passed"}.
std::string memoryCheckJson(const MemoryCheck& check);

}  // namespace stvd::tool
