// SPDX-License-Identifier: BSL-1.0
#include "perch/core/bounded_vector.hpp"

#include <doctest/doctest.h>

using perch::errc;

TEST_CASE("bounded_vector: fills to capacity, then reports capacity_exceeded") {
  perch::workspace ws;
  auto made = perch::bounded_vector<int>::make(ws, 3);
  REQUIRE(made);
  auto& v = *made;
  CHECK(v.empty());
  CHECK(v.push_back(1));
  CHECK(v.push_back(2));
  CHECK(v.push_back(3));
  auto full = v.push_back(4);
  REQUIRE(!full);
  CHECK(full.error().code == errc::capacity_exceeded);
  CHECK(full.error().needed == 4);
  CHECK(v.size() == 3);
  int sum = 0;
  for (int x : v) sum += x;
  CHECK(sum == 6);
  v.truncate(1);
  CHECK(v.back() == 1);
  v.pop_back();
  CHECK(v.empty());
}
