// SPDX-License-Identifier: BSL-1.0
/// \file
/// The constraints of the paper (table 2 and the viability check) and the platforms' additions.
/// Each returns by how much a window misses (in `unit`), 0 when it passes; `name` appears in
/// diagnostics. All are aggregates: `perch::max_slope{.max_deg = 30}`.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <string_view>

#include "perch/analysis/clearance.hpp"
#include "perch/analysis/measures.hpp"
#include "perch/core/mask.hpp"
#include "perch/core/result.hpp"

namespace perch {

namespace detail {
[[nodiscard]] constexpr bool finite_non_negative(float v) noexcept {
  return v >= 0 && v <= std::numeric_limits<float>::max();  // false for NaN and ∞
}
}  // namespace detail

/// Claw-region mean diameter within [min_mm, max_mm] (Li et al. 2025: 30–110 mm), by at least
/// `margin_px` image pixels at the window's scale; and the window's lower-tercile diameter
/// (`window_measures::diameter_low_mm`) at least `min_mm` + `low_margin_px` pixels.
///
/// The margin is the measurement's uncertainty: a diameter read off a mask is good to a fraction
/// of a pixel, and the eq. 3 scorer prefers the smallest graspable diameter, so without a margin
/// the ranking seeks out exactly the windows whose diameter is within noise of `min_mm`. 0 gives
/// the paper's plain range.
///
/// The lower tercile guards the minimum against a rough outline: bumps, spurs and leaves on a
/// limb's outline only add to its cross-sections, so on a limb near `min_mm` they lift the mean
/// by a pixel or more and the scorer then picks exactly such limbs. On a smooth outline the
/// lower tercile lies a few tenths of a pixel below the mean and the mean's test decides (its
/// effect on the synthetic population of `tests/pli_accuracy_test.cpp`: docs/accuracy-log.md).
/// Windows whose `diameter_low_mm` is 0 (not measured) skip this test; a negative
/// `low_margin_px` turns it off.
struct diameter_range {
  static constexpr std::string_view name = "diameter";
  static constexpr std::string_view unit = "mm";
  float min_mm = 30.0f;
  float max_mm = 110.0f;
  float margin_px = 0.5f;
  float low_margin_px = 0.25f;
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    const float margin_mm = margin_px * m.mm_per_px;
    const float low_miss = low_margin_px >= 0 && m.diameter_low_mm > 0
                               ? min_mm + low_margin_px * m.mm_per_px - m.diameter_low_mm
                               : 0.0f;
    return std::max({min_mm + margin_mm - m.claw_diameter_mm,
                     m.claw_diameter_mm - (max_mm - margin_mm), low_miss, 0.0f});
  }
  [[nodiscard]] status validate() const noexcept {
    if (!detail::finite_non_negative(min_mm) || !detail::finite_non_negative(max_mm) ||
        !detail::finite_non_negative(margin_px) ||
        !(std::abs(low_margin_px) <= std::numeric_limits<float>::max()))
      return fail(errc::invalid_parameter, "diameter_range");
    if (min_mm > max_mm) return fail(errc::range_inverted, "diameter_range");
    return {};
  }
};

/// The claw's diameter is known well enough to say it fits: the claw-region diameter, give or
/// take `uncertainty_px` image pixels at the window's scale, still within [min_mm, max_mm].
/// A mask's widths are good to `width_uncertainty_px`, and a cross-section adds its own
/// measuring error (rms 0.4–0.6 px; paper eq. 3 seeks the smallest graspable diameter, so
/// without it the ranking picks windows known only to within that error of the limit). So a
/// 30–40 mm limb drawn 2–3 px wide may be 20 mm or 50 mm: not known to be graspable, and
/// reported as `resolution`, not as a perch.
/// A diameter outside the range itself passes here: that is `diameter_range`'s to report.
struct resolved_diameter {
  static constexpr std::string_view name = "resolution";
  static constexpr std::string_view unit = "px";
  static constexpr float measuring_error_px = 0.5f;  ///< a cross-section's own, beyond the outline's
  float min_mm = 30.0f;
  float max_mm = 110.0f;
  float uncertainty_px = width_uncertainty_px + measuring_error_px;
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    if (!(m.mm_per_px > 0)) return 1.0f;
    if (m.claw_diameter_mm < min_mm || m.claw_diameter_mm > max_mm) return 0.0f;
    const float d_px = m.claw_diameter_mm / m.mm_per_px;
    // Against the smallest diameter, the lower tercile where it was measured: an outline's
    // bumps and spurs only widen a limb, so the mean reads rough thin limbs high.
    const float low_px =
        m.diameter_low_mm > 0 ? std::min(d_px, m.diameter_low_mm / m.mm_per_px) : d_px;
    return std::max({min_mm / m.mm_per_px + uncertainty_px - low_px,
                     d_px + uncertainty_px - max_mm / m.mm_per_px, 0.0f});
  }
  [[nodiscard]] status validate() const noexcept {
    if (!detail::finite_non_negative(min_mm) || !detail::finite_non_negative(max_mm) ||
        !detail::finite_non_negative(uncertainty_px))
      return fail(errc::invalid_parameter, "resolved_diameter");
    if (min_mm > max_mm) return fail(errc::range_inverted, "resolved_diameter");
    return {};
  }
};

/// Slope to the true horizontal at most `max_deg` (the claw: 35°), both of the window's chord
/// and of the limb's local tangent at every point of it (`window_measures::slope_max_deg`).
struct max_slope {
  static constexpr std::string_view name = "max_slope";
  static constexpr std::string_view unit = "deg";
  float max_deg = 35.0f;
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    return std::max(std::max(m.slope_deg, m.slope_max_deg) - max_deg, 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!(detail::finite_non_negative(max_deg) && max_deg <= 90.0f))
      return fail(errc::invalid_parameter, "max_slope.max_deg");
    return {};
  }
};

/// Slope at least `min_deg` (trunk perching on near-vertical stems).
struct min_slope {
  static constexpr std::string_view name = "min_slope";
  static constexpr std::string_view unit = "deg";
  float min_deg = 70.0f;
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    return std::max(min_deg - m.slope_deg, 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!(detail::finite_non_negative(min_deg) && min_deg <= 90.0f))
      return fail(errc::invalid_parameter, "min_slope.min_deg");
    return {};
  }
};

/// Largest |curvature| over the window at most `max_per_mm` (a filter only, not a score:
/// paper §"Exemplar results", point 2). Default 1/150 mm⁻¹: bends tighter than a 15 cm radius.
struct max_curvature {
  static constexpr std::string_view name = "max_curvature";
  static constexpr std::string_view unit = "1/mm";
  float max_per_mm = 1.0f / 150.0f;
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    return std::max(m.curvature_max_per_mm - max_per_mm, 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!(detail::finite_non_negative(max_per_mm) && max_per_mm > 0))
      return fail(errc::invalid_parameter, "max_curvature.max_per_mm");
    return {};
  }
};

/// The limb turns by at most `max_deg` over a drone's width around any point of the window
/// (`window_measures::bend_deg`): no kink or tight curve under or beside the drone's body.
/// 20° over the claw's 180 mm is a bend radius of about 0.5 m.
struct max_bend {
  static constexpr std::string_view name = "bend";
  static constexpr std::string_view unit = "deg";
  float max_deg = 20.0f;
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    return std::max(m.bend_deg - max_deg, 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!(detail::finite_non_negative(max_deg) && max_deg <= 180.0f))
      return fail(errc::invalid_parameter, "max_bend.max_deg");
    return {};
  }
};

/// The limb's outline under the window stays at least `margin_px` pixels inside the frame
/// (`window_measures::border_px`): a limb cut by the frame is not known beyond it, and the
/// last pixels of a segmenter's mask are its least reliable.
struct image_border {
  static constexpr std::string_view name = "border";
  static constexpr std::string_view unit = "px";
  float margin_px = 3.0f;
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    return std::max(margin_px - m.border_px, 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!detail::finite_non_negative(margin_px))
      return fail(errc::invalid_parameter, "image_border.margin_px");
    return {};
  }
};

/// The window's piece of mask holds something up (`window_measures::grounded`): connected to a
/// trunk that reaches the bottom of the frame, or the main tree. A detached piece of mask (a
/// segmenter's gap, a blob of foliage) is not a perch, whatever its shape. Misses by 1.
struct supported {
  static constexpr std::string_view name = "supported";
  static constexpr std::string_view unit = "";
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    return m.grounded ? 0.0f : 1.0f;
  }
  [[nodiscard]] status validate() const noexcept { return {}; }
};

/// The window never turns back along its chord by more than `tolerance_mm` (paper
/// §"Exemplar results", point 1: branch reversal).
struct monotonic {
  static constexpr std::string_view name = "monotonic";
  static constexpr std::string_view unit = "mm";
  float tolerance_mm = 5.0f;
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    return std::max(m.reversal_mm - tolerance_mm, 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!detail::finite_non_negative(tolerance_mm))
      return fail(errc::invalid_parameter, "monotonic.tolerance_mm");
    return {};
  }
};

/// Every point of the window is at least `margin_mm` from the surface of every other limb
/// thicker than a twig, beyond its own surface (`window_context::limb_gap_mm`): the claw reaches
/// that far around the limb as it closes, so a side limb, the parent at a fork, a limb crossing
/// in front or behind, or a second tree there would be in its way. Twigs (`obstacle_options`)
/// are compliant and do not count. Like a width, a gap between two outlines read off a mask is
/// good to `width_uncertainty_px`, so the gap must reach the margin plus `uncertainty_px`
/// image pixels at the window's scale to be known clear.
struct clearance {
  static constexpr std::string_view name = "clearance";
  static constexpr std::string_view unit = "mm";
  float margin_mm = 70.0f;
  float uncertainty_px = width_uncertainty_px;
  [[nodiscard]] float operator()(const window_measures& m,
                                 const window_context& context) const noexcept {
    const float needed = margin_mm + uncertainty_px * m.mm_per_px;
    return std::max(needed - context.limb_gap_mm(needed), 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!detail::finite_non_negative(margin_mm) || !detail::finite_non_negative(uncertainty_px))
      return fail(errc::invalid_parameter, "clearance");
    return {};
  }
};

/// The claw closes on one limb: over the window the limb's radius (`radius_max_px`) swells
/// above its lower tercile (`radius_low_px`) by at most `taper` of it plus `uncertainty_px`.
/// A limb under a drone's width is close to a cylinder: it tapers by a few per cent, and the
/// distance map along a bending centreline ripples by a few more (`taper`, 10 %). Where the
/// mask is much wider than that at some point of the window, something else is there: another
/// limb lying along this one or merging into it (the two read as one wide band), the crotch of
/// a fork the window runs onto, a blob of foliage. The claw would close on that, not on the
/// limb measured. A swelling is read from one outline against the same outline elsewhere, so an
/// outline drawn uniformly wider or narrower shifts both alike; a local bump of the outline is
/// `outline_uncertainty_px`. Windows whose `radius_low_px` is 0 (not measured) pass.
struct one_limb {
  static constexpr std::string_view name = "one_limb";
  static constexpr std::string_view unit = "px";
  float taper = 0.1f;
  float uncertainty_px = outline_uncertainty_px;
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    if (!(m.radius_low_px > 0)) return 0.0f;
    const float allowed = uncertainty_px + taper * m.radius_low_px;
    return std::max(m.radius_max_px - m.radius_low_px - allowed, 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!detail::finite_non_negative(taper) || !detail::finite_non_negative(uncertainty_px))
      return fail(errc::invalid_parameter, "one_limb");
    return {};
  }
};

/// At most `max_share` of the band `margin_mm` around the branch is other tree (twigs, crossing
/// branches, leaves): the paper's failure case of a perch buried in small branches.
struct clutter {
  static constexpr std::string_view name = "clutter";
  static constexpr std::string_view unit = "share";
  float margin_mm = 60.0f;
  float max_share = 0.15f;
  [[nodiscard]] float operator()(const window_measures&,
                                 const window_context& context) const noexcept {
    return std::max(context.band(margin_mm).share() - max_share, 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!(detail::finite_non_negative(margin_mm) && detail::finite_non_negative(max_share)))
      return fail(errc::invalid_parameter, "clutter");
    return {};
  }
};

/// Free space above the branch for a drone that lands from above (Zheng et al. 2023) or a
/// wing span (Zufferey et al. 2022): at most `max_share` tree in the box `width_mm` ×
/// `height_mm` over the perch.
struct free_space_above {
  static constexpr std::string_view name = "free_space_above";
  static constexpr std::string_view unit = "share";
  float width_mm = 400.0f;
  float height_mm = 250.0f;
  float max_share = 0.02f;
  [[nodiscard]] float operator()(const window_measures&,
                                 const window_context& context) const noexcept {
    return std::max(context.above(width_mm, height_mm).share() - max_share, 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!(detail::finite_non_negative(width_mm) && width_mm > 0 &&
          detail::finite_non_negative(height_mm) && height_mm > 0 &&
          detail::finite_non_negative(max_share)))
      return fail(errc::invalid_parameter, "free_space_above");
    return {};
  }
};

/// The circle of one tether length around the perch is free of other branches, so the
/// tethered mass wraps without tangling (Lan et al. 2024).
struct free_circle {
  static constexpr std::string_view name = "free_circle";
  static constexpr std::string_view unit = "share";
  float radius_mm = 500.0f;
  float max_share = 0.02f;
  [[nodiscard]] float operator()(const window_measures&,
                                 const window_context& context) const noexcept {
    return std::max(context.circle(radius_mm).share() - max_share, 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!(detail::finite_non_negative(radius_mm) && radius_mm > 0 &&
          detail::finite_non_negative(max_share)))
      return fail(errc::invalid_parameter, "free_circle");
    return {};
  }
};

/// Standard gravity, m/s².
inline constexpr float standard_gravity = 9.80665f;

/// Bending stress (MPa) at the root of a cantilevered round branch (paper eq. 4):
/// σ = M·r/I = 4·F·L/(π·r³), F = m·g, M = F·L, I = π·r⁴/4.
[[nodiscard]] inline float bending_stress_mpa(float mass_kg, float radius_mm,
                                              float lever_mm) noexcept {
  // No cross-section: more than any modulus of rupture.
  if (!(radius_mm > 0)) return std::numeric_limits<float>::max();
  const float force_n = mass_kg * standard_gravity;
  const float r_m = radius_mm / 1000.0f;
  const float sigma_pa =
      4.0f * force_n * (lever_mm / 1000.0f) / (std::numbers::pi_v<float> * r_m * r_m * r_m);
  return sigma_pa / 1.0e6f;
}

/// The branch holds the drone: σ (eq. 4, lever = horizontal distance from where the branch leaves
/// its parent, radius = claw-region radius) ≤ modulus of rupture / safety factor. Default
/// modulus 27 MPa: the weakest of 88 North American species in the Wood Handbook.
struct bending_stress {
  static constexpr std::string_view name = "bending_stress";
  static constexpr std::string_view unit = "MPa";
  float mass_kg = 1.5f;
  float modulus_of_rupture_mpa = 27.0f;
  float safety_factor = 2.0f;
  float load_factor = 1.0f;  ///< > 1 for dynamic perching (an ornithopter's impact)
  [[nodiscard]] float operator()(const window_measures& m) const noexcept {
    const float sigma = load_factor * bending_stress_mpa(mass_kg, 0.5f * m.claw_diameter_mm,
                                                         m.origin_horizontal_mm);
    return std::max(sigma - modulus_of_rupture_mpa / safety_factor, 0.0f);
  }
  [[nodiscard]] status validate() const noexcept {
    if (!(detail::finite_non_negative(mass_kg) && mass_kg > 0 &&
          detail::finite_non_negative(modulus_of_rupture_mpa) && modulus_of_rupture_mpa > 0 &&
          detail::finite_non_negative(safety_factor) && safety_factor > 0 &&
          detail::finite_non_negative(load_factor) && load_factor > 0))
      return fail(errc::invalid_parameter, "bending_stress");
    return {};
  }
};

}  // namespace perch
