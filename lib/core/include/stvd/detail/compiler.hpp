// Compiler hints for the propagation's inner loops.
#pragma once

#include <cstdint>

#if defined(__GNUC__) || defined(__clang__)
/// Forces inlining of the small functions of the inner loops, where a call
/// would stop vectorisation.
#define STVD_ALWAYS_INLINE inline __attribute__((always_inline))
#define STVD_ALWAYS_INLINE_LAMBDA __attribute__((always_inline))
/// Asks for the loop over SIMD lanes to be vectorised (OpenMP SIMD, honoured
/// with -fopenmp-simd; no OpenMP runtime is involved).
#define STVD_SIMD_LOOP _Pragma("omp simd")
#else
#define STVD_ALWAYS_INLINE inline
#define STVD_ALWAYS_INLINE_LAMBDA
#define STVD_SIMD_LOOP
#endif

/// The relaxation loops are compiled twice on x86-64, for the baseline ISA
/// and for x86-64-v3 (AVX2 + FMA, 2013 and later), and the loader picks the
/// version the processor supports (GNU ifunc). The STVD chain kernel runs
/// eight lanes per instruction with AVX2 instead of four. Define
/// STVD_NO_TARGET_CLONES to build the baseline only. GCC only: clang (up
/// to 14 at least) refuses target_clones on function templates.
#if defined(__x86_64__) && defined(__gnu_linux__) && !defined(STVD_NO_TARGET_CLONES) && \
    !defined(__clang__) && defined(__GNUC__) && __GNUC__ >= 8
#define STVD_HOT_LOOP __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define STVD_HOT_LOOP
#endif

namespace stvd::detail {
/// Asks for the cache line holding `address` to be loaded (a hint; never
/// faults). On x86-64 it is a volatile asm statement rather than
/// __builtin_prefetch: GCC 12 drops __builtin_prefetch from the inlined STVD
/// loop (measured: not one prefetch instruction left in it).
///
/// The hint is T1 (the outer cache levels) rather than T0: what is asked for
/// is the next popped vertex's neighbourhood, some thirty lines not needed
/// before the current relaxation ends. Measured with the time stamp counter
/// on default STVD at 256^3, T1 took the gather phase from about 1280 to
/// about 950 cycles per pop; T2 gave the same as T1.
inline __attribute__((always_inline)) void prefetch(const void* address) {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
  asm volatile("prefetcht1 %0" : : "m"(*static_cast<const char*>(address)));
#elif defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(address, 0, 2);
#else
  (void)address;
#endif
}

/// prefetch() for every 64-byte line from the one holding *first to the one
/// holding the last byte of *last.
template <class T>
inline __attribute__((always_inline)) void prefetchRange(const T* first, const T* last) {
  constexpr std::uintptr_t kLine = 64;
  const auto end = reinterpret_cast<std::uintptr_t>(last + 1);
  for (auto line = reinterpret_cast<std::uintptr_t>(first) & ~(kLine - 1); line < end; line += kLine)
    prefetch(reinterpret_cast<const void*>(line));
}
}  // namespace stvd::detail
