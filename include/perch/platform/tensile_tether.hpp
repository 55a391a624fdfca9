// SPDX-License-Identifier: BSL-1.0
/// \file
/// Tensile perching (Lan et al. 2024, "Aerial tensile perching and disentangling mechanism for
/// long-term environmental monitoring"): a tethered mass wraps around a branch and the drone
/// hangs below it.
#pragma once

#include "perch/platform/platform.hpp"
#include "perch/policy/constraints.hpp"
#include "perch/policy/scorers.hpp"

namespace perch {

/// Tensile tether: no claw, so no upper diameter limit beyond what the tether can wrap (a
/// generous 400 mm); the branch must carry the load (eq. 4) and the circle of one tether
/// length around the perch must be free of other branches so the mass wraps without tangling
/// (the PLI paper's adaptation). Like every platform, a perch only on a supported piece of
/// mask, clear of the frame's border, with its diameter known to lie in range. Tether length and mass are illustrative defaults: set them
/// from your airframe. Ranked by eq. 3 over the same criteria, preferring level branches.
struct tensile_tether {
  static constexpr std::string_view name = "tensile-tether";
  static constexpr float max_slope_deg = 40.0f;
  platform_geometry geometry{.drone_width_mm = 150.0f, .claw_width_mm = 50.0f, .mass_kg = 1.0f,
                             .grasp_min_mm = 20.0f, .grasp_max_mm = 400.0f};
  all_of<supported, image_border, diameter_range, resolved_diameter, max_slope, max_curvature,
         bending_stress, free_circle>
      constraints{supported{},
                  image_border{},
                  diameter_range{geometry.grasp_min_mm, geometry.grasp_max_mm},
                  resolved_diameter{geometry.grasp_min_mm, geometry.grasp_max_mm},
                  max_slope{max_slope_deg},
                  max_curvature{},
                  bending_stress{geometry.mass_kg},
                  free_circle{.radius_mm = 500.0f, .max_share = 0.02f}};
  pli_penalty scorer{.lambda_slope = 0.7f, .lambda_diameter = 0.3f, .slope_max_deg = max_slope_deg,
                     .diameter_min_mm = geometry.grasp_min_mm,
                     .diameter_max_mm = geometry.grasp_max_mm,
                     .ideal_diameter_mm = geometry.grasp_min_mm};
};

}  // namespace perch
