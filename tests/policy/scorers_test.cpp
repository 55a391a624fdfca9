// SPDX-License-Identifier: BSL-1.0
#include "perch/policy/scorers.hpp"

#include <doctest/doctest.h>

#include "perch/policy/composites.hpp"

using perch::errc;

TEST_CASE("scorers: paper eq. 3 penalty") {
  const perch::pli_penalty p{};
  perch::window_measures m;
  m.slope_deg = 0;
  m.claw_diameter_mm = 30;
  CHECK(p(m) == doctest::Approx(0.0f));  // the ideal branch
  m.slope_deg = 35;
  m.claw_diameter_mm = 110;
  CHECK(p(m) == doctest::Approx(1.0f));  // the worst viable branch
  m.slope_deg = 17.5f;
  m.claw_diameter_mm = 70;
  CHECK(p(m) == doctest::Approx(0.8f * 0.5f + 0.2f * 0.5f));
  // A higher slope bias prefers the flatter, wider branch (paper appendix, Fig. compare-biases).
  perch::window_measures flat_wide, steep_thin;
  flat_wide.slope_deg = 5;
  flat_wide.claw_diameter_mm = 90;
  steep_thin.slope_deg = 25;
  steep_thin.claw_diameter_mm = 35;
  CHECK(p(flat_wide) < p(steep_thin));
  const perch::pli_penalty width_biased{.lambda_slope = 0.2f, .lambda_diameter = 0.8f};
  CHECK(width_biased(flat_wide) > width_biased(steep_thin));
}

TEST_CASE("scorers: lambda must sum to 1 within a tolerance, never by float equality") {
  CHECK(perch::pli_penalty{.lambda_slope = 0.7f, .lambda_diameter = 0.3f}.validate());
  CHECK(perch::pli_penalty{.lambda_slope = 0.1f + 0.2f, .lambda_diameter = 0.7f}.validate());
  CHECK(perch::pli_penalty{.lambda_slope = 0.7f, .lambda_diameter = 0.4f}.validate().error().code ==
        errc::weights_not_normalised);
  CHECK(perch::pli_penalty{.lambda_slope = 1.2f, .lambda_diameter = -0.2f}.validate().error().code ==
        errc::weights_not_normalised);
  CHECK(perch::pli_penalty{.slope_min_deg = 40.0f}.validate().error().code == errc::range_inverted);
  CHECK(perch::pli_penalty{.diameter_max_mm = std::nanf("")}.validate().error().code ==
        errc::invalid_parameter);
}

TEST_CASE("scorers: weighted_sum combines scorers and validates its weights") {
  using combined = perch::weighted_sum<perch::pli_penalty, perch::curvature_penalty>;
  const combined s{{0.75f, 0.25f}, {perch::pli_penalty{}, perch::curvature_penalty{}}};
  static_assert(perch::Scorer<combined>);
  perch::window_measures m;
  m.slope_deg = 35;
  m.claw_diameter_mm = 30;
  m.curvature_max_per_mm = 1.0f / 300.0f;  // half the curvature scale
  CHECK(s(m) == doctest::Approx(0.75f * 0.8f + 0.25f * 0.5f));
  CHECK(s.validate());
  CHECK(combined{{0.75f, 0.5f}, {}}.validate().error().code == errc::weights_not_normalised);
  CHECK(perch::lever_penalty{}.validate());
}
