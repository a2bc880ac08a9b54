// Arrays with one entry per voxel, backed by transparent huge pages where
// the system offers them.
//
// A propagation reads the state and the metric of each popped vertex's
// neighbours; on a 26-neighbourhood they lie in three slices, which are
// megabytes apart in memory once the grid is large, so every popped vertex
// touches a dozen or more pages per array. With 4 KiB pages these accesses
// miss the TLB; 2 MiB pages cover a whole front's neighbourhood with a few
// entries. Linux gives huge pages to a region that asks for them with
// madvise(MADV_HUGEPAGE) when transparent huge pages are in "madvise" mode
// (Debian's default); in "always" mode they come anyway, in "never" not at
// all, and elsewhere the advice is skipped. The pages must be advised
// before they are first written, hence reserve, advise, then fill.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace stvd {

/// Asks the kernel to back [data, data + bytes) with transparent huge pages
/// (only the 2 MiB-aligned part of it; smaller ranges are left alone).
/// Advice only: nothing changes where the system declines.
inline void adviseHugePages(void* data, std::size_t bytes) {
#if defined(__linux__) && defined(MADV_HUGEPAGE)
  constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + kHugePage - 1) & ~(kHugePage - 1);
  const std::uintptr_t last = (begin + bytes) & ~(kHugePage - 1);
  if (last > first) madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
#else
  (void)data;
  (void)bytes;
#endif
}

/// `count` copies of `value`, in storage advised for huge pages when it is
/// large enough to span some.
template <class T>
std::vector<T> makeLargeArray(std::size_t count, const T& value) {
  std::vector<T> array;
  array.reserve(count);
  adviseHugePages(array.data(), count * sizeof(T));
  array.assign(count, value);
  return array;
}

}  // namespace stvd
