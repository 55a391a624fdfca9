// SPDX-License-Identifier: BSL-1.0
#include "perch/core/assert.hpp"

#include <doctest/doctest.h>

namespace {
void quiet_handler(const char*, const char*, int, const char*) noexcept {}
}  // namespace

TEST_CASE("assert: the handler hook can be installed and restored") {
  const auto previous = perch::set_assert_handler(&quiet_handler);
  const bool restored_ours = perch::set_assert_handler(previous) == &quiet_handler;
  CHECK(restored_ours);
  PERCH_ASSERT(1 + 1 == 2, "arithmetic holds");  // a passing assertion does nothing
}
