/// \file
/// The tendon-driven claw quadrotor of Li et al. 2025 ("Tendon-driven grasping for tree-perching
/// drones"), the paper's reference platform and perch's default.
#pragma once

#include "perch/platform/platform.hpp"
#include "perch/policy/constraints.hpp"
#include "perch/policy/scorers.hpp"

namespace perch {

/// Tendon-driven claw: grasps 30–110 mm diameters with a 70 mm claw on a 180 mm wide, 1.5 kg
/// drone, on branches at most 35° from horizontal (Li et al. 2025, as used by the PLI paper),
/// gently curved, monotonic, strong enough (paper eq. 4), and not buried in twigs.
/// Ranked by paper eq. 3 with λ_slope 0.8, λ_diameter 0.2.
struct tendon_claw {
  static constexpr std::string_view name = "tendon-claw";
  platform_geometry geometry{};
  all_of<diameter_range, max_slope, max_curvature, monotonic, bending_stress, clearance>
      constraints{diameter_range{30.0f, 110.0f}, max_slope{35.0f}, max_curvature{},
                  monotonic{}, bending_stress{1.5f}, clearance{}};
  pli_penalty scorer{};
};

}  // namespace perch
