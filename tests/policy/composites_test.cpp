// SPDX-License-Identifier: BSL-1.0
#include "perch/policy/composites.hpp"

#include <doctest/doctest.h>

#include <string_view>

#include "perch/policy/constraints.hpp"

namespace {
// A user's constraint: the perch must be in the lower half of a 1000 px tall image.
struct lower_half {
  static constexpr std::string_view name = "lower_half";
  static constexpr std::string_view unit = "px";
  float operator()(const perch::window_measures& m) const noexcept {
    return m.centre.y < 500 ? static_cast<float>(500 - m.centre.y) : 0.0f;
  }
};
struct missing_unit {
  static constexpr std::string_view name = "x";
  float operator()(const perch::window_measures&) const noexcept { return 0; }
};
struct not_noexcept {
  static constexpr std::string_view name = "x";
  static constexpr std::string_view unit = "x";
  float operator()(const perch::window_measures&) const { return 0; }
};
}  // namespace

static_assert(perch::Constraint<lower_half>);
static_assert(perch::GeometricConstraint<perch::max_slope>);
static_assert(perch::ContextConstraint<perch::clearance>);
static_assert(!perch::GeometricConstraint<perch::clearance>);
static_assert(!perch::Constraint<missing_unit>);
static_assert(!perch::Constraint<not_noexcept>);
static_assert(!perch::Constraint<int>);

using nested = perch::all_of<perch::max_slope, perch::all_of<lower_half, perch::clearance>,
                             perch::diameter_range>;
static_assert(perch::Constraint<nested>);
static_assert(perch::leaf_count<nested> == 4);

TEST_CASE("composites: all_of flattens its leaves in order for diagnostics") {
  const nested c{perch::max_slope{20.0f}, perch::all_of<lower_half, perch::clearance>{},
                 perch::diameter_range{}};
  const auto names = perch::leaf_names(c);
  CHECK(names[0] == "max_slope");
  CHECK(names[1] == "lower_half");
  CHECK(names[2] == "clearance");
  CHECK(names[3] == "diameter");
  CHECK(c.validate());
  const nested bad{perch::max_slope{20.0f}, {}, perch::diameter_range{90.0f, 10.0f}};
  CHECK(bad.validate().error().code == perch::errc::range_inverted);
}
