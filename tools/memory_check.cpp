#include "memory_check.hpp"

#include "command_line.hpp"

namespace stvd::tool {

std::string memoryCheckJson(const MemoryCheck& memory) {
  return "{\"needed_bytes\": " + std::to_string(memory.neededBytes) +
         ", \"resident_bytes\": " + std::to_string(memory.residentBytes) + ", \"available_bytes\": " +
         (memory.available ? std::to_string(memory.available->bytes) : "null") + ", \"limited_by\": " +
         (memory.available ? jsonString(memory.available->limitedBy) : "null") + ", \"check\": " +
         jsonString(memory.skipped ? "skipped" : memory.available ? "passed" : "not made (available memory unknown)") +
         "}";
}

MemoryCheck checkMemory(const std::string& input, std::uint64_t neededBytes, const std::string& what, bool skip) {
  MemoryCheck check;
  check.neededBytes = neededBytes;
  check.residentBytes = residentMemoryBytes();
  check.available = availableMemory();
  check.skipped = skip;
  if (!skip && check.available && neededBytes > check.available->bytes)
    throw ToolError(kExitMemory, input + ": " + memoryShortfall(neededBytes, *check.available, what) +
                                     "; add --no-memory-check to run anyway");
  return check;
}

}  // namespace stvd::tool
