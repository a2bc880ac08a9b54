#include "stvd/system/memory.hpp"

#include <sys/resource.h>

#include <fstream>
#include <sstream>

#include "stvd/front_end/number_text.hpp"

namespace stvd {
namespace {

/// A "Key:   1234 kB" line of a /proc file, in bytes; 0 when missing.
std::uint64_t procField(const std::string& file, const std::string& key) {
  std::ifstream in(file);
  std::string line;
  while (std::getline(in, line)) {
    if (line.compare(0, key.size() + 1, key + ":") != 0) continue;
    std::istringstream words(line.substr(key.size() + 1));
    std::uint64_t value = 0;
    std::string unit;
    words >> value >> unit;
    return unit == "kB" ? value * 1024 : value;
  }
  return 0;
}

std::optional<std::uint64_t> numberIn(const std::string& file) {
  std::ifstream in(file);
  std::string text;
  if (!(in >> text) || text == "max") return std::nullopt;
  try {
    return std::stoull(text);
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

/// What the control group of this process still allows, when it is limited.
std::optional<std::uint64_t> controlGroupRoom() {
  std::ifstream groups("/proc/self/cgroup");
  std::string line;
  while (std::getline(groups, line)) {
    // "0::/path" (v2) or "N:memory:/path" (v1).
    const std::size_t first = line.find(':'), second = line.find(':', first + 1);
    if (first == std::string::npos || second == std::string::npos) continue;
    const std::string controllers = line.substr(first + 1, second - first - 1);
    const std::string group = line.substr(second + 1);
    std::optional<std::uint64_t> limit, usage;
    if (controllers.empty()) {
      limit = numberIn("/sys/fs/cgroup" + group + "/memory.max");
      usage = numberIn("/sys/fs/cgroup" + group + "/memory.current");
    } else if (controllers.find("memory") != std::string::npos) {
      limit = numberIn("/sys/fs/cgroup/memory" + group + "/memory.limit_in_bytes");
      usage = numberIn("/sys/fs/cgroup/memory" + group + "/memory.usage_in_bytes");
    }
    // cgroup v1 reports "no limit" as a huge number.
    if (limit && usage && *limit < (std::uint64_t{1} << 60)) return *limit > *usage ? *limit - *usage : 0;
  }
  return std::nullopt;
}

}  // namespace

std::optional<AvailableMemory> availableMemory() {
  std::optional<AvailableMemory> least;
  auto consider = [&](std::uint64_t bytes, const char* limitedBy) {
    if (!least || bytes < least->bytes) least = AvailableMemory{bytes, limitedBy};
  };
  if (const std::uint64_t system = procField("/proc/meminfo", "MemAvailable"))
    consider(system, "MemAvailable in /proc/meminfo");
  if (const auto group = controlGroupRoom()) consider(*group, "the control group's memory limit");
  rlimit limit{};
  if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY) {
    const std::uint64_t size = procField("/proc/self/status", "VmSize");
    consider(limit.rlim_cur > size ? limit.rlim_cur - size : 0, "the address-space limit, ulimit -v");
  }
  return least;
}

std::uint64_t residentMemoryBytes() { return procField("/proc/self/status", "VmRSS"); }

std::string memoryText(std::uint64_t bytes) {
  const double mib = static_cast<double>(bytes) / (1024.0 * 1024.0);
  if (mib >= 1024.0) return text::fixed(mib / 1024.0, 1) + " GiB";
  return text::fixed(mib, 0) + " MiB";
}

std::string memoryShortfall(std::uint64_t neededBytes, const AvailableMemory& available, const std::string& what) {
  return "the run needs about " + memoryText(neededBytes) + " more memory (" + what + ") but only " +
         memoryText(available.bytes) + " are available (limit: " + available.limitedBy + ")";
}

}  // namespace stvd
