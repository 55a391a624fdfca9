// SPDX-License-Identifier: BSL-1.0
/// \file
/// How much a rule's measure flickers from frame to frame with the segmenter's noise alone: the
/// tracker keeps a confirmed target whose spot misses a rule by no more than this (for a few
/// frames, flagged doubtful), and never for a larger miss. One table, one physical reason per
/// rule; a rule it does not name (or a custom platform's own) gets none: any miss of it counts
/// in full.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include <array>
#include <string_view>

#include "perch/policy/constraints.hpp"

namespace perch {

/// A rule's frame-to-frame measurement noise, in image pixels for lengths (converted to the
/// rule's unit with the window's scale when the rule speaks mm) or in degrees for angles.
struct rule_noise {
  std::string_view constraint{};  ///< the constraint's `name`
  float amount = 0;               ///< px for `px` and `mm` rules, degrees for `deg` rules
};

/// The noise of each rule of the built-in platforms (`perch/policy/constraints.hpp`), and why.
inline constexpr std::array<rule_noise, 8> rule_noises{{
    // The limb's outline against the frame's edge: an outline is good to about a pixel.
    {image_border::name, 1.0f},
    // A gap between two limbs' outlines: each is good to about a pixel, and they err apart.
    {clearance::name, 2.0f},
    // The claw region's mean cross-section: single cross-sections err by about a pixel, the
    // mean over the region by half of one (rms 0.4-0.6 px on the synthetic population).
    {diameter_range::name, 0.5f},
    {resolved_diameter::name, 0.5f},
    // The steepest local tangent of a centreline that shifts by a pixel, tangents taken over
    // about 30 px of limb: atan(1/30) is 2 degrees.
    {max_slope::name, 2.0f},
    {min_slope::name, 2.0f},
    // A change between two such tangents, a drone width apart; each errs by the same 2
    // degrees, and a bend's tangents are fitted over longer stretches.
    {max_bend::name, 2.0f},
    // A reversal along the chord: a centreline point is good to about a pixel.
    {monotonic::name, 1.0f},
}};

/// How far a window may miss `constraint` (in the rule's `unit`) and still be within the
/// measurement's noise, at `mm_per_px` (the window's scale); 0 for a rule without a known noise
/// or a scale that is not positive and finite for a mm rule.
[[nodiscard]] constexpr float measurement_noise(std::string_view constraint, std::string_view unit,
                                                float mm_per_px) noexcept {
  for (const rule_noise& r : rule_noises) {
    if (r.constraint != constraint) continue;
    if (unit == "px" || unit == "deg") return r.amount;
    if (unit == "mm" && mm_per_px > 0 && mm_per_px < 1e6f) return r.amount * mm_per_px;
    return 0;
  }
  return 0;
}

}  // namespace perch
