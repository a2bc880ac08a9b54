#include "memory_check.hpp"

#include "command_line.hpp"

namespace stvd::tool {

std::string memoryText(std::uint64_t bytes) {
  const double mib = static_cast<double>(bytes) / (1024.0 * 1024.0);
  if (mib >= 1024.0) return fixed(mib / 1024.0, 1) + " GiB";
  return fixed(mib, 0) + " MiB";
}

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
    throw ToolError(kExitMemory, input + ": the run needs about " + memoryText(neededBytes) + " more memory (" + what +
                                     ") but only " + memoryText(check.available->bytes) + " are available (limit: " +
                                     check.available->limitedBy + "); add --no-memory-check to run anyway");
  return check;
}

}  // namespace stvd::tool
