/// \file
/// `--annotate`: a picture of `find_perch`'s answer a person reads at a glance.
#pragma once

#include <cstdint>

#include "perch/core/image.hpp"
#include "perch/pli.hpp"
#include "png/png.hpp"

namespace perch::tool {

/// Draws, over the photo (or the mask when `photo` is null) dimmed to gray:
///   - skeleton pixels pruning removed, faint gray;
///   - the pruned skeleton graph's branches coloured by diameter (perceptual ramp from 0 to
///     twice the platform's largest graspable diameter), nodes as dots (junction white, end
///     orange, trunk node ringed cyan);
///   - near-miss windows (failed one constraint only) faint red, named by their constraint;
///   - the ranked sites' windows in green, numbered;
///   - the chosen perch as a yellow rectangle claw width × diameter along the branch, labelled
///     "slope 12 deg, d 54 mm";
///   - a status line and a legend.
/// The picture has the input's size. `photo`, when given, must have the mask's size.
[[nodiscard]] image<png::rgb8> annotate(const perch_result& r, const platform_geometry& geometry,
                                        const image<std::uint8_t>& mask,
                                        const image<png::rgb8>* photo);

}  // namespace perch::tool
