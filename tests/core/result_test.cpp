// SPDX-License-Identifier: BSL-1.0
#include "perch/core/result.hpp"

#include <doctest/doctest.h>

#include <string_view>

using perch::errc;
using perch::result;

namespace {
result<int> half(int v) {
  if (v % 2 != 0) return perch::fail(errc::invalid_parameter, "v");
  return v / 2;
}
result<int> quarter(int v) {
  auto h = half(v);
  if (!h) return perch::unexpected{h.error()};
  return half(*h);
}
perch::status check_positive(int v) {
  if (v <= 0) return perch::fail(errc::invalid_parameter, "v");
  return {};
}
perch::status check_both(int a, int b) {
  PERCH_TRY(check_positive(a));
  PERCH_TRY(check_positive(b));
  return {};
}
}  // namespace

TEST_CASE("result: value, error and propagation like std::expected") {
  auto ok = quarter(8);
  REQUIRE(ok.has_value());
  CHECK(*ok == 2);
  CHECK(ok.value() == 2);
  CHECK(ok.value_or(7) == 2);

  auto bad = quarter(6);
  REQUIRE(!bad);
  CHECK(bad.error().code == errc::invalid_parameter);
  CHECK(bad.error().detail == "v");
  CHECK(bad.value_or(7) == 7);

  CHECK(check_both(1, 2));
  CHECK(check_both(1, -2).error().code == errc::invalid_parameter);
}

TEST_CASE("result: every error code has an actionable message") {
  for (int c = 0; c <= static_cast<int>(errc::no_valid_depth); ++c) {
    const std::string_view message = perch::to_string(static_cast<errc>(c));
    CHECK(message.size() > 20);
    CHECK(message != "unknown perch error");
  }
  const perch::error e{errc::workspace_too_small, "workspace", 4096};
  CHECK(e.message().find("bytes") != std::string_view::npos);
  CHECK(e.needed == 4096);
}

TEST_CASE("result: constexpr use") {
  constexpr result<int> r = 3;
  static_assert(r.has_value());
  constexpr perch::status s = perch::fail(errc::range_inverted);
  static_assert(!s.has_value());
  CHECK(r.value() == 3);
}
