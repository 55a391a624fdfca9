// SPDX-License-Identifier: BSL-1.0
/// \file
/// The treecreeper drone of Li et al. 2025 ("Treecreeper drone: bird-inspired perching on
/// vertical tree trunks"): a claw plus a microspine tail that perch on near-vertical trunks.
#pragma once

#include "perch/platform/platform.hpp"
#include "perch/policy/constraints.hpp"
#include "perch/policy/scorers.hpp"

namespace perch {

/// Treecreeper: perches on near-vertical stems (slope ≥ 70°), large diameters, straight;
/// ranked toward vertical (ideal 90°) and the widest stems (firmest grip for the tail). Like
/// every platform, a perch only on a supported piece of mask, clear of the frame's border,
/// with its diameter known to lie in range.
/// Sizes are illustrative defaults: set them from your airframe.
struct treecreeper {
  static constexpr std::string_view name = "treecreeper";
  static constexpr float min_slope_deg = 70.0f;
  platform_geometry geometry{.drone_width_mm = 250.0f, .claw_width_mm = 100.0f, .mass_kg = 1.5f,
                             .grasp_min_mm = 100.0f, .grasp_max_mm = 600.0f};
  all_of<supported, image_border, diameter_range, resolved_diameter, min_slope, max_curvature,
         monotonic>
      constraints{supported{},
                  image_border{},
                  diameter_range{geometry.grasp_min_mm, geometry.grasp_max_mm},
                  resolved_diameter{geometry.grasp_min_mm, geometry.grasp_max_mm},
                  min_slope{min_slope_deg},
                  max_curvature{.max_per_mm = 1.0f / 400.0f},
                  monotonic{}};
  pli_penalty scorer{.lambda_slope = 0.6f, .lambda_diameter = 0.4f, .slope_min_deg = min_slope_deg,
                     .slope_max_deg = 90.0f, .ideal_slope_deg = 90.0f,
                     .diameter_min_mm = geometry.grasp_min_mm,
                     .diameter_max_mm = geometry.grasp_max_mm,
                     .ideal_diameter_mm = geometry.grasp_max_mm};
};

}  // namespace perch
