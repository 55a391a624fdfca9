// SPDX-License-Identifier: BSL-1.0
/// \file
/// `--annotate`: a picture of `find_perch`'s answer a person reads at a glance.
#pragma once

#include <cstdint>
#include <string_view>

#include "perch/core/image.hpp"
#include "perch/pli.hpp"
#include "perch/track.hpp"
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

/// One frame of `perch track`, for `annotate_tracks`.
struct track_picture {
  int frame = 0;                               ///< its number in the sequence
  int width = 0, height = 0;                   ///< the input frame's size
  const image<std::uint8_t>* mask = nullptr;   ///< its mask (null: the frame could not be read)
  const perch_result* found = nullptr;         ///< its analysis (null: none)
  const tracking_result* tracked = nullptr;    ///< the tracker's answer (required)
  std::string_view error;                      ///< why there is no analysis, when there is none
  int last_change_frame = -1;                  ///< the frame of the latest change of target (-1: none)
  target_change last_change{};                 ///< that change
};

/// A picture of the tracker's view of one frame, `out_width` pixels wide (the input's width
/// when ≤ 0 or larger; the height in proportion), in `annotate`'s style:
///   - the mask in gray (each pixel the share of tree it covers when scaled down) and the
///     pruned skeleton's branches coloured by diameter, as `annotate` draws them;
///   - every track at its smoothed position: its window along the limb and "#id",
///     confirmed green (a dot), tentative light blue (a ring), lost gray (a faint ring);
///   - the target as `annotate` draws the chosen perch (claw × diameter rectangle, heading
///     arrow), labelled "#id target: slope, d, heading" and, while doubtful, the rule it fails (or
///     "unseen N frames");
///   - a status line (frame, status, target), under it the change of target in this frame and
///     its reason, on red, or the latest change before it, faint;
///   - a legend, in the corner that hides the least tree.
[[nodiscard]] image<png::rgb8> annotate_tracks(const track_picture& picture, const platform_geometry& geometry,
                                               int out_width);

}  // namespace perch::tool
