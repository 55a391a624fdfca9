// SPDX-License-Identifier: BSL-1.0
/// \file
/// The metamorphic quadrotor of Zheng et al. 2023 ("Metamorphic aerial robot capable of mid-air
/// shape morphing for rapid perching"): lands on a branch from above and clamps it with its arms.
#pragma once

#include "perch/platform/platform.hpp"
#include "perch/policy/constraints.hpp"
#include "perch/policy/scorers.hpp"

namespace perch {

/// Metamorphic quadrotor: descends onto the branch, so the space above the perch must be free
/// for the drone's width and height (the PLI paper's adaptation); near-level branches within
/// the arms' clamping range. Like every platform, a perch only on a supported piece of mask,
/// clear of the frame's border, with its diameter known to fit (`resolved_diameter`); like the
/// tendon claw, its arms close on one limb (`one_limb`) with no kink under its body
/// (`max_bend`). Sizes are illustrative defaults: set them from your airframe.
struct metamorphic_quadrotor {
  static constexpr std::string_view name = "metamorphic";
  static constexpr float max_slope_deg = 20.0f;
  platform_geometry geometry{.drone_width_mm = 300.0f, .claw_width_mm = 120.0f, .mass_kg = 1.2f,
                             .grasp_min_mm = 25.0f, .grasp_max_mm = 90.0f};
  landing_constraints constraints = landing_on_limb(
      geometry, max_slope_deg, bending_stress{geometry.mass_kg},
      free_space_above{.width_mm = geometry.drone_width_mm, .height_mm = 200.0f,
                       .max_share = 0.02f});
  pli_penalty scorer{.lambda_slope = 0.8f, .lambda_diameter = 0.2f, .slope_max_deg = max_slope_deg,
                     .diameter_min_mm = geometry.grasp_min_mm,
                     .diameter_max_mm = geometry.grasp_max_mm,
                     .ideal_diameter_mm = geometry.grasp_min_mm};
};

}  // namespace perch
