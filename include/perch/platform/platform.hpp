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
#include "perch/policy/constraints.hpp"
#include "perch/policy/scorers.hpp"

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

/// The constraints of a drone that lands on top of a limb and closes on it (the metamorphic
/// quadrotor's arms, the ornithopter's feet): the mask's facts every platform has (supported,
/// border, diameter known to be in range), one limb under it with no kink under its body, its
/// slope, the paper's filters and eq. 4, and free space above for its approach.
using landing_constraints =
    all_of<supported, image_border, diameter_range, resolved_diameter, one_limb, max_slope,
           max_bend, max_curvature, monotonic, bending_stress, free_space_above>;

/// `landing_constraints` for `geometry` (its grasp range), with the platform's own slope limit,
/// bending stress (mass and load) and free space above.
[[nodiscard]] constexpr landing_constraints landing_on_limb(const platform_geometry& geometry,
                                                            float max_slope_deg,
                                                            bending_stress stress,
                                                            free_space_above space) noexcept {
  return landing_constraints{supported{},
                             image_border{},
                             diameter_range{geometry.grasp_min_mm, geometry.grasp_max_mm},
                             resolved_diameter{geometry.grasp_min_mm, geometry.grasp_max_mm},
                             one_limb{},
                             max_slope{max_slope_deg},
                             max_bend{},
                             max_curvature{},
                             monotonic{},
                             stress,
                             space};
}

/// A platform: `P::name`, `p.geometry`, `p.constraints` (a Constraint, usually `all_of<...>`),
/// `p.scorer` (a Scorer).
template <class P>
concept Platform = requires(const P& p) {
  { P::name } -> std::convertible_to<std::string_view>;
  { p.geometry } -> std::convertible_to<platform_geometry>;
  requires Constraint<std::remove_cvref_t<decltype(p.constraints)>>;
  requires Scorer<std::remove_cvref_t<decltype(p.scorer)>>;
};

namespace detail {

/// Whether the stock parts of `p` state its geometry's numbers: every `diameter_range` and
/// `resolved_diameter` its grasp range, every `bending_stress` its mass, a `pli_penalty` scorer
/// its grasp range. A platform writes each number once, in `geometry`, and builds its parts
/// from it; parts changed apart from it (or a geometry changed after they were built from it)
/// would judge one range and prune or rank by another.
template <Platform P>
[[nodiscard]] constexpr status parts_agree(const P& p) noexcept {
  const platform_geometry& g = p.geometry;
  status out{};
  for_each_leaf(p.constraints, [&](const auto& leaf, std::size_t) {
    using L = std::remove_cvref_t<decltype(leaf)>;
    if constexpr (std::same_as<L, diameter_range> || std::same_as<L, resolved_diameter>) {
      if (out && (leaf.min_mm != g.grasp_min_mm || leaf.max_mm != g.grasp_max_mm))
        out = fail(errc::invalid_parameter, "platform: a diameter range is not geometry's");
    } else if constexpr (std::same_as<L, bending_stress>) {
      if (out && leaf.mass_kg != g.mass_kg)
        out = fail(errc::invalid_parameter, "platform: bending_stress.mass_kg is not geometry's");
    }
  });
  using S = std::remove_cvref_t<decltype(p.scorer)>;
  if constexpr (std::same_as<S, pli_penalty>) {
    if (out && (p.scorer.diameter_min_mm != g.grasp_min_mm ||
                p.scorer.diameter_max_mm != g.grasp_max_mm))
      out = fail(errc::invalid_parameter, "platform: the scorer's diameters are not geometry's");
  }
  return out;
}

}  // namespace detail

/// Validates a platform's geometry, constraints and scorer, and that its stock parts state its
/// geometry's numbers (`detail::parts_agree`: `invalid_parameter` naming the part that does
/// not).
template <Platform P>
[[nodiscard]] constexpr status validate_platform(const P& p) noexcept {
  PERCH_TRY(p.geometry.validate());
  PERCH_TRY(validate_policy(p.constraints));
  PERCH_TRY(validate_policy(p.scorer));
  return detail::parts_agree(p);
}

}  // namespace perch
