// SPDX-License-Identifier: BSL-1.0
/// \file
/// The perching ornithopter of Zufferey et al. 2022 ("How ornithopters can perch autonomously
/// on a branch"): a flapping-wing drone that perches dynamically, at speed.
#pragma once

#include "perch/platform/platform.hpp"
#include "perch/policy/constraints.hpp"
#include "perch/policy/scorers.hpp"

namespace perch {

/// Ornithopter: the wing span must clear other branches above the perch; the impact of a
/// dynamic perch loads the branch more than a hover (load factor 3 in eq. 4) and raises the
/// minimum diameter; near-level branches only (the PLI paper's adaptation). Like every
/// platform, a perch only on a supported piece of mask, clear of the frame's border, with its
/// diameter known to fit; its feet close on one limb (`one_limb`) with no kink under its body
/// (`max_bend`). Sizes are
/// illustrative defaults: set them from your airframe.
struct ornithopter {
  static constexpr std::string_view name = "ornithopter";
  static constexpr float max_slope_deg = 15.0f;
  platform_geometry geometry{.drone_width_mm = 200.0f, .claw_width_mm = 60.0f, .mass_kg = 0.7f,
                             .grasp_min_mm = 40.0f, .grasp_max_mm = 100.0f};
  landing_constraints constraints =
      landing_on_limb(geometry, max_slope_deg,
                      bending_stress{.mass_kg = geometry.mass_kg, .load_factor = 3.0f},
                      free_space_above{.width_mm = 1500.0f, .height_mm = 300.0f, .max_share = 0.03f});
  pli_penalty scorer{.lambda_slope = 0.9f, .lambda_diameter = 0.1f, .slope_max_deg = max_slope_deg,
                     .diameter_min_mm = geometry.grasp_min_mm,
                     .diameter_max_mm = geometry.grasp_max_mm,
                     .ideal_diameter_mm = geometry.grasp_min_mm};
};

}  // namespace perch
