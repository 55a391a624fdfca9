/// \file
/// A cache prefetch hint, for the stages whose accesses scatter over the image.
#pragma once

namespace perch::detail {

/// A hint to fetch the cache line holding `p` (no effect on the result; nothing where the
/// compiler has no such builtin). `p` need not be dereferenceable.
inline void prefetch(const void* p) noexcept {
#if defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(p);
#else
  (void)p;
#endif
}

}  // namespace perch::detail
