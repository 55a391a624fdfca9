// SPDX-License-Identifier: BSL-1.0
/// \file
/// The one assertion macro for programmer errors (broken preconditions), and the hook a user
/// redirects it with. Data errors never assert: they come back as a status (see result.hpp).
#pragma once

#include <cstdlib>

namespace perch {

/// Signature of a user hook called when a `PERCH_ASSERT` fails, before `std::abort()`.
using assert_handler = void (*)(const char* expression, const char* file, int line,
                                const char* message) noexcept;

namespace detail {
inline assert_handler& assert_hook() noexcept {
  static assert_handler hook = nullptr;
  return hook;
}
}  // namespace detail

/// Installs `handler` (nullptr for none) and returns the previous one. A firmware user can log,
/// blink, or reset from it; perch aborts if the hook returns.
inline assert_handler set_assert_handler(assert_handler handler) noexcept {
  const assert_handler previous = detail::assert_hook();
  detail::assert_hook() = handler;
  return previous;
}

/// Called by `PERCH_ASSERT` on failure: runs the hook, then aborts.
[[noreturn]] inline void assert_failed(const char* expression, const char* file, int line,
                                       const char* message) noexcept {
  if (const assert_handler hook = detail::assert_hook()) hook(expression, file, line, message);
  std::abort();
}

}  // namespace perch

/// `PERCH_ASSERT(condition, message)`: checked unless `NDEBUG` is defined (force it on with
/// `PERCH_ENABLE_ASSERTS`, off with `PERCH_DISABLE_ASSERTS`), or define `PERCH_ASSERT` yourself
/// before including perch to route it anywhere.
#ifndef PERCH_ASSERT
#if defined(PERCH_DISABLE_ASSERTS) || (defined(NDEBUG) && !defined(PERCH_ENABLE_ASSERTS))
#define PERCH_ASSERT(condition, message) static_cast<void>(sizeof((condition) ? 1 : 0))
#else
#define PERCH_ASSERT(condition, message)                                                  \
  ((condition) ? static_cast<void>(0)                                                    \
               : ::perch::assert_failed(#condition, __FILE__, __LINE__, message))
#endif
#endif
