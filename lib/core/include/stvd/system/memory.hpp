// How much memory a run may still take: what the system, the process's
// control group and its address-space limit leave. Entry points compare
// their estimate of a run with it before they allocate (Linux; elsewhere
// nothing is known and no check is made).
#pragma once

#include <cstdint>
#include <optional>
#include <string>

namespace stvd {

struct AvailableMemory {
  std::uint64_t bytes = 0;
  /// Which limit it is, for messages: "MemAvailable in /proc/meminfo",
  /// "the control group's memory limit" or "the address-space limit, ulimit -v".
  std::string limitedBy;
};

/// The smallest of: the memory the system has available now (MemAvailable:
/// free memory plus caches it can drop; swap not counted), what the
/// process's control group still allows (cgroup v2 memory.max minus
/// memory.current, or v1 limit minus usage) and what the address-space
/// limit (RLIMIT_AS) leaves above the process's current size. Empty when
/// none of them can be read.
std::optional<AvailableMemory> availableMemory();

/// Resident memory of this process now (VmRSS of /proc/self/status); 0
/// when unknown.
std::uint64_t residentMemoryBytes();

/// "3.2 GiB", "850 MiB".
std::string memoryText(std::uint64_t bytes);

/// Why a run that still needs `neededBytes` (`what` says for what: "STVD on
/// 132,892 domain voxels") does not fit into `available`, as the front ends
/// say it: "the run needs about 2.5 GiB more memory (...) but only 1.0 GiB
/// are available (limit: ...)". The caller decides that it does not fit
/// and adds the file's name and how to run anyway.
std::string memoryShortfall(std::uint64_t neededBytes, const AvailableMemory& available, const std::string& what);

}  // namespace stvd
