// SPDX-License-Identifier: BSL-1.0
/// \file
/// Cache prefetch hints, for the stages whose accesses scatter over the image or jump from row
/// to row.
#pragma once

#include <cstddef>

// Always inlined: GCC 12 deletes a call to a function that does nothing but prefetch, as if it
// had no effect, and the hint with it (so callers prefetch inline too, not in a helper).
#if defined(__GNUC__) || defined(__clang__)
#define PERCH_PREFETCH_INLINE [[gnu::always_inline]] inline
#else
#define PERCH_PREFETCH_INLINE inline
#endif

namespace perch::detail {

/// A hint to fetch the cache line holding `p` (no effect on the result; nothing where the
/// compiler has no such builtin). `p` need not be dereferenceable.
PERCH_PREFETCH_INLINE void prefetch(const void* p) noexcept {
#if defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(p);
#else
  (void)p;
#endif
}

/// Images of at least this many pixels fetch ahead where a pass jumps from row to row: the
/// hints pay once a pass's rows outgrow the last-level cache, and below that they buy nothing
/// or cost a little (timings on two hosts: docs/performance-log.md).
inline constexpr std::size_t fetch_ahead_from = std::size_t{1} << 20;

/// A hint to fetch the cache lines holding the `n` elements from `first` (64-byte lines).
template <class T>
PERCH_PREFETCH_INLINE void prefetch_span(const T* first, std::ptrdiff_t n) noexcept {
  constexpr auto step = static_cast<std::ptrdiff_t>(sizeof(T) < 64 ? 64 / sizeof(T) : 1);
  for (std::ptrdiff_t i = 0; i < n; i += step) prefetch(first + i);
  if (n > 0) prefetch(first + (n - 1));
}

}  // namespace perch::detail
