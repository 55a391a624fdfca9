// SPDX-License-Identifier: BSL-1.0
/// \file
/// The `Platform` concept: a drone and its perching mechanism as a type — its geometry, a pack
/// of constraints and one scorer, composed at compile time.
#pragma once

#include <cmath>
#include <concepts>
#include <string_view>

#include "perch/core/result.hpp"
#include "perch/policy/composites.hpp"
#include "perch/policy/concepts.hpp"

namespace perch {

/// The drone's size and what its mechanism can grasp.
struct platform_geometry {
  float drone_width_mm = 180.0f;  ///< window length along the branch
  float claw_width_mm = 70.0f;    ///< central region whose diameter the mechanism grasps
  float mass_kg = 1.5f;           ///< perching mass (for bending stress)
  float grasp_min_mm = 30.0f;     ///< smallest graspable diameter (pruning weights, eq. 1)
  float grasp_max_mm = 110.0f;    ///< largest graspable diameter

  [[nodiscard]] status validate() const noexcept {
    for (const float v : {drone_width_mm, claw_width_mm, mass_kg, grasp_min_mm, grasp_max_mm})
      if (!(std::isfinite(v) && v > 0)) return fail(errc::invalid_parameter, "platform_geometry");
    if (grasp_min_mm > grasp_max_mm) return fail(errc::range_inverted, "platform_geometry.grasp");
    return {};
  }
};

/// A platform: `P::name`, `p.geometry`, `p.constraints` (a Constraint, usually `all_of<...>`),
/// `p.scorer` (a Scorer).
template <class P>
concept Platform = requires(const P& p) {
  { P::name } -> std::convertible_to<std::string_view>;
  { p.geometry } -> std::convertible_to<platform_geometry>;
  requires Constraint<std::remove_cvref_t<decltype(p.constraints)>>;
  requires Scorer<std::remove_cvref_t<decltype(p.scorer)>>;
};

/// Validates a platform's geometry, constraints and scorer.
template <Platform P>
[[nodiscard]] constexpr status validate_platform(const P& p) noexcept {
  PERCH_TRY(p.geometry.validate());
  PERCH_TRY(validate_policy(p.constraints));
  return validate_policy(p.scorer);
}

}  // namespace perch
