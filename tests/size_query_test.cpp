// SPDX-License-Identifier: BSL-1.0
#include <doctest/doctest.h>

#include <cstddef>

#include "perch/pli.hpp"

TEST_CASE("find_perch_workspace_bytes: grows with the frame and never wraps") {
  const std::size_t small = perch::find_perch_workspace_bytes(640, 480);
  const std::size_t large = perch::find_perch_workspace_bytes(32768, 32768);
  CHECK(small > 0);
  if (sizeof(std::size_t) >= 8)
    CHECK(large > small);
  else
    CHECK(large == 0);  // more than a 32-bit address space: no buffer could hold it
}
