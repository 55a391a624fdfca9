// SPDX-License-Identifier: BSL-1.0
/// \file
/// `--annotate`: a picture of `find_perch`'s answer a person reads at a glance.
#pragma once

#include <cstdint>

#include "perch/core/image.hpp"
#include "perch/pli.hpp"
#include "png/png.hpp"

namespace perch::tool {

/// The clearance a platform keeps around the grasped limb (`perch::clearance`): every other limb
/// thicker than a twig must stay `margin_mm` + `uncertainty_px` (at the window's scale) beyond
/// the limb's surface under the window. `margin_mm` < 0: the platform has no such rule.
struct clearance_envelope {
  float margin_mm = -1.0f;
  float uncertainty_px = 0.0f;
};

/// The colour of the chosen window's clearance envelope (drawn opaque, for tests to find).
inline constexpr png::rgb8 envelope_rgb{255, 110, 255};

/// Draws, over the photo (or the mask when `photo` is null) dimmed to gray:
///   - skeleton pixels pruning removed, faint gray;
///   - the pruned skeleton graph's branches coloured by diameter (perceptual ramp from 0 to
///     twice the platform's largest graspable diameter), nodes as dots (junction white, end
///     orange, trunk node ringed cyan);
///   - near-miss windows (failed one constraint only) faint red, named by their constraint;
///   - the ranked sites' windows in green, numbered;
///   - near misses labelled with their constraint and by how much they missed
///     ("clearance 12 mm"); a clearance near miss also gets its envelope, faint red;
///   - the chosen window's clearance envelope (`clearance_envelope`): the outline of its
///     centreline points dilated by their radius + the margin, the region that must be free of
///     other limbs, in `envelope_rgb`;
///   - the chosen perch as a yellow rectangle claw width × diameter along the branch, labelled
///     "#1 slope 12 deg, d 54 mm" (the other ranked sites "#2", "#3", ...);
///   - a status line (its scale reduced until it fits the width) and a legend of exactly what
///     is drawn, in the corner that hides the least tree, never the title or the chosen perch.
/// The picture has the input's size. `photo`, when given, must have the mask's size.
[[nodiscard]] image<png::rgb8> annotate(const perch_result& r, const platform_geometry& geometry,
                                        const clearance_envelope& envelope,
                                        const image<std::uint8_t>& mask,
                                        const image<png::rgb8>* photo);

}  // namespace perch::tool
