// SPDX-License-Identifier: BSL-1.0
/// \file
/// The tendon-driven claw quadrotor of Li et al. 2025 ("Tendon-driven grasping for tree-perching
/// drones"), the paper's reference platform and perch's default.
#pragma once

#include "perch/platform/platform.hpp"
#include "perch/policy/constraints.hpp"
#include "perch/policy/scorers.hpp"

namespace perch {

/// Tendon-driven claw: grasps 30–110 mm diameters with a 70 mm claw on a 180 mm wide, 1.5 kg
/// drone (Li et al. 2025, as used by the PLI paper). A window (one drone width of limb) is a
/// safe perch when, at every point of it:
///  - its piece of mask is grounded (`supported`) and its outline is 3 px inside the frame
///    (`image_border`);
///  - the claw-region diameter is within 30–110 mm (`diameter_range`), and still is give or
///    take what a mask's outline and a cross-section's measuring leave unknown
///    (`resolved_diameter`), and the mask there is this one limb, not it and another lying
///    along it or merging into it (`one_limb`);
///  - the limb's tangent is at most 35° from horizontal (`max_slope`), it turns by at most 20°
///    over a drone width around any point (`max_bend`), gently curved and monotonic;
///  - it holds the drone (paper eq. 4, `bending_stress`);
///  - every other limb thicker than a 20 mm twig is at least 70 mm (the claw's reach as it
///    closes) from its surface (`clearance`); widths and gaps with the margins of a mask's
///    outline (`outline_uncertainty_px`).
/// Ranked by paper eq. 3 with λ_slope 0.8, λ_diameter 0.2.
/// The drone's numbers are written once, in `geometry` and the constants below; the constraints
/// and the scorer are built from them.
struct tendon_claw {
  static constexpr std::string_view name = "tendon-claw";
  static constexpr float max_slope_deg = 35.0f;  ///< steepest limb the claw holds on
  static constexpr float claw_reach_mm = 70.0f;  ///< how far the fingers sweep round the limb
  platform_geometry geometry{.drone_width_mm = 180.0f, .claw_width_mm = 70.0f, .mass_kg = 1.5f,
                             .grasp_min_mm = 30.0f, .grasp_max_mm = 110.0f};
  all_of<supported, image_border, diameter_range, resolved_diameter, one_limb, max_slope,
         max_bend, max_curvature, monotonic, bending_stress, clearance>
      constraints{supported{},
                  image_border{},
                  diameter_range{geometry.grasp_min_mm, geometry.grasp_max_mm, 0.0f},
                  resolved_diameter{geometry.grasp_min_mm, geometry.grasp_max_mm},
                  one_limb{},
                  max_slope{max_slope_deg},
                  max_bend{20.0f},
                  max_curvature{},
                  monotonic{},
                  bending_stress{geometry.mass_kg},
                  clearance{claw_reach_mm}};
  pli_penalty scorer{.slope_max_deg = max_slope_deg,
                     .diameter_min_mm = geometry.grasp_min_mm,
                     .diameter_max_mm = geometry.grasp_max_mm,
                     .ideal_diameter_mm = geometry.grasp_min_mm};
};

}  // namespace perch
