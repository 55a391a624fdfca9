// SPDX-License-Identifier: BSL-1.0
#include "perch/platform.hpp"

#include <doctest/doctest.h>

#include <string_view>

// The five platforms of the paper model the concept.
static_assert(perch::Platform<perch::tendon_claw>);
static_assert(perch::Platform<perch::tensile_tether>);
static_assert(perch::Platform<perch::metamorphic_quadrotor>);
static_assert(perch::Platform<perch::ornithopter>);
static_assert(perch::Platform<perch::treecreeper>);

namespace {
// A scorer that forgot `noexcept` and returns a string: not a Scorer, so not a Platform.
struct wrong_scorer {
  static constexpr std::string_view name = "wrong";
  std::string_view operator()(const perch::window_measures&) const { return "low"; }
};
struct platform_with_wrong_scorer {
  static constexpr std::string_view name = "wrong";
  perch::platform_geometry geometry{};
  perch::all_of<perch::max_slope> constraints{};
  wrong_scorer scorer{};
};
struct platform_without_geometry {
  static constexpr std::string_view name = "no-geometry";
  perch::max_slope constraints{};
  perch::pli_penalty scorer{};
};
}  // namespace
static_assert(!perch::Scorer<wrong_scorer>);
static_assert(!perch::Platform<platform_with_wrong_scorer>);
static_assert(!perch::Platform<platform_without_geometry>);

TEST_CASE("platforms: every shipped platform validates, with the paper's defaults") {
  CHECK(perch::validate_platform(perch::tendon_claw{}));
  CHECK(perch::validate_platform(perch::tensile_tether{}));
  CHECK(perch::validate_platform(perch::metamorphic_quadrotor{}));
  CHECK(perch::validate_platform(perch::ornithopter{}));
  CHECK(perch::validate_platform(perch::treecreeper{}));
  const perch::tendon_claw claw{};
  CHECK(claw.geometry.drone_width_mm == 180.0f);
  CHECK(claw.geometry.claw_width_mm == 70.0f);
  CHECK(claw.geometry.mass_kg == 1.5f);
  CHECK(claw.scorer.lambda_slope == 0.8f);
  CHECK(claw.scorer.lambda_diameter == 0.2f);
  CHECK(std::get<perch::max_slope>(claw.constraints.parts).max_deg == 35.0f);
  CHECK(std::get<perch::diameter_range>(claw.constraints.parts).min_mm == 30.0f);
  CHECK(std::get<perch::diameter_range>(claw.constraints.parts).max_mm == 110.0f);
}

TEST_CASE("platforms: bad parameters are named statuses") {
  perch::tendon_claw claw{};
  claw.scorer.lambda_slope = 0.9f;  // 0.9 + 0.2 != 1
  CHECK(perch::validate_platform(claw).error().code == perch::errc::weights_not_normalised);
  claw = {};
  claw.geometry.drone_width_mm = 0.0f;
  CHECK(perch::validate_platform(claw).error().code == perch::errc::invalid_parameter);
  claw = {};
  std::get<perch::diameter_range>(claw.constraints.parts) = {120.0f, 30.0f};
  CHECK(perch::validate_platform(claw).error().code == perch::errc::range_inverted);
}

TEST_CASE("platforms: parts that do not state the geometry's numbers are refused") {
  // Built from its geometry (aggregate initialisation): agrees.
  const perch::tendon_claw heavier{.geometry = {.mass_kg = 2.5f, .grasp_min_mm = 40.0f}};
  CHECK(perch::validate_platform(heavier));
  CHECK(std::get<perch::bending_stress>(heavier.constraints.parts).mass_kg == 2.5f);
  // The geometry changed after its parts were built from it: they would judge another range.
  perch::tendon_claw changed{};
  changed.geometry.grasp_min_mm = 40.0f;
  CHECK(perch::validate_platform(changed).error().code == perch::errc::invalid_parameter);
  perch::tendon_claw mass{};
  mass.geometry.mass_kg = 3.0f;
  CHECK(perch::validate_platform(mass).error().code == perch::errc::invalid_parameter);
  perch::tendon_claw scorer{};
  scorer.scorer.diameter_max_mm = 90.0f;
  CHECK(perch::validate_platform(scorer).error().code == perch::errc::invalid_parameter);
  perch::tendon_claw resolution{};
  std::get<perch::resolved_diameter>(resolution.constraints.parts).min_mm = 35.0f;
  CHECK(perch::validate_platform(resolution).error().code == perch::errc::invalid_parameter);
}
