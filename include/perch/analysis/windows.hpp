// SPDX-License-Identifier: BSL-1.0
/// \file
/// Sliding windows along a branch (paper §"Analyse Branches"): one drone width of arc length,
/// moved by a stride, never across a junction; and the measures of each window.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

#include "perch/analysis/attitude.hpp"
#include "perch/analysis/measures.hpp"
#include "perch/analysis/scale.hpp"
#include "perch/core/bounded_vector.hpp"
#include "perch/core/geometry.hpp"
#include "perch/core/result.hpp"
#include "perch/core/workspace.hpp"

namespace perch {

/// Which end of a branch polyline lies toward the trunk (where the branch leaves its parent).
enum class origin_end : std::uint8_t { front, back };

/// One limb as the window stage reads it: an ordered centreline with the distance to the
/// background (radius, px) at each point. Points are in the analysed image's coordinates;
/// `offset` maps them to the input image's (added to every reported pixel).
struct branch_geometry {
  std::span<const pixel> points{};
  std::span<const float> radius_px{};
  std::int32_t limb = -1;  ///< reported as `window_measures::limb`
  std::int32_t component = -1;
  origin_end origin = origin_end::front;
  pixel offset{};
  /// Index of `points[0]` in the whole limb polyline when `points` is a stretch of it: added
  /// to the reported `first`, `last` and `middle` so they index the whole polyline.
  std::uint32_t first_index = 0;
  /// Optional diameter (px) at each point (`cross_section_diameters`); empty: 2·d − 1 from
  /// `radius_px`.
  std::span<const float> diameter_px{};
  /// The frame `points + offset` lie in (the analysed image), for `window_measures::border_px`;
  /// 0 × 0: not measured.
  int frame_width = 0;
  int frame_height = 0;
  /// Whether the branch's piece of mask holds something up (`window_measures::grounded`).
  bool grounded = true;
};

/// Window geometry and measuring options. Defaults: the tendon-claw drone of Li et al. 2025.
struct window_options {
  float drone_width_mm = 180.0f;  ///< window length (arc length)
  float stride_mm = 20.0f;        ///< distance between window starts
  float claw_width_mm = 70.0f;    ///< central region whose mean diameter the claw grasps
  /// Curvature stencil (see `curvature_options`) as a length on the branch: bends that matter
  /// to a claw are centimetres long, pixel staircases are not. At least 3 px.
  float curvature_stencil_mm = 40.0f;
  attitude camera{};

  [[nodiscard]] status validate() const noexcept {
    for (const float v : {drone_width_mm, stride_mm, claw_width_mm, curvature_stencil_mm})
      if (!(std::isfinite(v) && v > 0)) return fail(errc::invalid_parameter, "window_options");
    return camera.validate();
  }
  /// The curvature stencil in px at `mm_per_px`.
  [[nodiscard]] curvature_options curvature_at(float mm_per_px) const noexcept {
    const float px = curvature_stencil_mm / mm_per_px;
    return {px < 3.0f ? 3 : (px > 64.0f ? 64 : static_cast<int>(std::lround(px)))};
  }
};

/// Floats of scratch `measure_windows` needs for a branch of `n` points.
[[nodiscard]] constexpr std::size_t window_scratch_floats(std::size_t n) noexcept { return 8 * n; }

/// Measures every window of `branch` and appends them to `out`.
///
/// Windows are `drone_width_mm` of arc long (at the global scale, refined once by the
/// window's local scale when the policy gives one), start every `stride_mm` from the branch's
/// first point, and end inside the branch: a branch shorter than one window yields none.
/// `scratch` holds at least `window_scratch_floats(points.size())` floats.
/// Errors: `capacity_exceeded` when `out` is full (needed = windows so far + 1).
/// Complexity: O(n + windows × window points).
template <ScalePolicy Scale>
[[nodiscard]] status measure_windows(const branch_geometry& branch, const Scale& scale,
                                     float global_mm_per_px, std::span<float> scratch,
                                     bounded_vector<window_measures>& out,
                                     const window_options& options = {}) noexcept {
  const std::size_t n = branch.points.size();
  PERCH_ASSERT(branch.radius_px.size() == n, "measure_windows: radius size");
  PERCH_ASSERT(branch.diameter_px.empty() || branch.diameter_px.size() == n,
               "measure_windows: diameter size");
  PERCH_ASSERT(scratch.size() >= window_scratch_floats(n), "measure_windows: scratch");
  if (n < 2) return {};
  std::span<float> arc = scratch.first(n);
  std::span<float> kappa = scratch.subspan(n, n);
  std::span<float> work = scratch.subspan(2 * n, 3 * n);
  std::span<float> tangent_x = scratch.subspan(5 * n, n);
  std::span<float> tangent_y = scratch.subspan(6 * n, n);
  std::span<float> bend = scratch.subspan(7 * n, n);
  arc_lengths(branch.points, arc);
  curvature_profile(branch.points, kappa, work, options.curvature_at(global_mm_per_px));
  tangent_profile(branch.points, arc, branch.radius_px, tangent_x, tangent_y);
  bend_profile(arc, tangent_x, tangent_y, 0.5f * options.drone_width_mm / global_mm_per_px, bend);
  const point2f h = options.camera.horizon();
  // Each point's slope and the gap between its outline and the frame's edge (px), once
  // (windows overlap), in the tangents' place, which nothing reads after this.
  std::span<float> slope = tangent_x;
  std::span<float> border_gap = tangent_y;
  const bool framed = branch.frame_width > 0 && branch.frame_height > 0;
  for (std::size_t i = 0; i < n; ++i) {
    slope[i] = slope_to_horizon_deg(point2f(tangent_x[i], tangent_y[i]), h);
    const pixel p{branch.points[i].x + branch.offset.x, branch.points[i].y + branch.offset.y};
    const int edge = std::min({p.x, p.y, branch.frame_width - 1 - p.x, branch.frame_height - 1 - p.y});
    border_gap[i] = framed ? static_cast<float>(edge) - branch.radius_px[i]
                           : std::numeric_limits<float>::max();
  }
  const float total_px = arc[n - 1];

  // Origin end, in local coordinates, and arc length measured from it.
  const bool from_front = branch.origin == origin_end::front;
  const point2f origin = to_point(from_front ? branch.points.front() : branch.points.back());

  auto index_at = [&](float s) {  // first point with arc ≥ s
    return static_cast<std::size_t>(std::lower_bound(arc.begin(), arc.end(), s) - arc.begin());
  };
  auto last_at = [&](float s) {  // last point with arc ≤ s
    const auto it = std::upper_bound(arc.begin(), arc.end(), s);
    return static_cast<std::size_t>(it - arc.begin()) - 1;
  };
  auto to_image = [&](pixel p) { return pixel{p.x + branch.offset.x, p.y + branch.offset.y}; };
  auto diameter_at = [&](std::size_t i) {
    return branch.diameter_px.empty() ? diameter_px(branch.radius_px[i]) : branch.diameter_px[i];
  };

  const float stride_px = options.stride_mm / global_mm_per_px;
  for (float start = 0; start < total_px; start += stride_px) {
    float mm_per_px = global_mm_per_px;
    float length_px = options.drone_width_mm / mm_per_px;
    if (start + length_px > total_px + 1e-3f) break;
    std::size_t a = index_at(start);
    std::size_t b = last_at(start + length_px);
    if (b <= a) continue;
    // Local scale (depth): measured on this window's pixels; the window is then re-cut to one
    // drone width at that scale and measured again for its position.
    auto local_at = [&](std::size_t first, std::size_t last) {
      const std::size_t count = last - first + 1;
      return scale.local(branch.points.subspan(first, count), branch.offset,
                         to_image(branch.points[(first + last) / 2]),
                         work.first(std::min(work.size(), count)), global_mm_per_px);
    };
    local_scale local = local_at(a, b);
    if (local.mm_per_px != mm_per_px && local.mm_per_px > 0) {
      mm_per_px = local.mm_per_px;
      length_px = options.drone_width_mm / mm_per_px;
      if (start + length_px > total_px + 1e-3f) continue;
      b = last_at(start + length_px);
      if (b <= a) continue;
      local = local_at(a, b);
      local.mm_per_px = mm_per_px;
    }
    const std::span<const pixel> pts = branch.points.subspan(a, b - a + 1);
    const float mid_arc = 0.5f * (arc[a] + arc[b]);
    std::size_t m = index_at(mid_arc);
    if (m > a && mid_arc - arc[m - 1] < arc[m] - mid_arc) --m;

    window_measures w;
    w.limb = branch.limb;
    w.component = branch.component;
    w.first = branch.first_index + static_cast<std::uint32_t>(a);
    w.last = branch.first_index + static_cast<std::uint32_t>(b);
    w.middle = branch.first_index + static_cast<std::uint32_t>(m);
    w.centre = to_image(branch.points[m]);
    w.start_px = arc[a];
    w.length_px = arc[b] - arc[a];
    w.mm_per_px = mm_per_px;
    w.slope_deg = slope_to_horizon_deg(to_point(pts.back()) - to_point(pts.front()), h);
    w.slope_fit_deg = fitted_slope_deg(pts, h);
    float kmax = 0;
    float ksum = 0;
    float slope_max = 0, bend_max = 0;
    float border = std::numeric_limits<float>::max();
    float dmin = 1e30f, dmax = 0, dsum = 0, claw_sum = 0;
    std::size_t claw_count = 0;
    const float claw_half_px = 0.5f * options.claw_width_mm / mm_per_px;
    for (std::size_t i = a; i <= b; ++i) {
      kmax = std::max(kmax, std::abs(kappa[i]));
      slope_max = std::max(slope_max, slope[i]);
      bend_max = std::max(bend_max, bend[i]);
      border = std::min(border, border_gap[i]);
      ksum += std::abs(kappa[i]);
      const float d = diameter_at(i);
      dmin = std::min(dmin, d);
      dmax = std::max(dmax, d);
      dsum += d;
      if (std::abs(arc[i] - arc[m]) <= claw_half_px) {
        claw_sum += d;
        ++claw_count;
      }
    }
    const auto count = static_cast<float>(b - a + 1);
    w.curvature_max_per_mm = kmax / mm_per_px;
    w.curvature_mean_per_mm = ksum / count / mm_per_px;
    w.diameter_min_mm = dmin * mm_per_px;
    w.diameter_max_mm = dmax * mm_per_px;
    w.diameter_mean_mm = dsum / count * mm_per_px;
    w.claw_diameter_mm =
        (claw_count > 0 ? claw_sum / static_cast<float>(claw_count) : diameter_at(m)) *
        mm_per_px;
    // The lower tercile, selected in `work` (free again once the local scale is measured).
    const std::size_t low_count = std::min(b - a + 1, work.size());
    for (std::size_t i = 0; i < low_count; ++i) work[i] = diameter_at(a + i);
    const auto low_rank = static_cast<std::ptrdiff_t>((low_count - 1) / 3);
    std::nth_element(work.begin(), work.begin() + low_rank,
                     work.begin() + static_cast<std::ptrdiff_t>(low_count));
    w.diameter_low_mm = work[static_cast<std::size_t>(low_rank)] * mm_per_px;
    w.reversal_mm = reversal_px(pts) * mm_per_px;
    w.slope_max_deg = slope_max;
    w.bend_deg = bend_max;
    w.border_px = border;
    w.grounded = branch.grounded;
    const float along = from_front ? arc[m] : total_px - arc[m];
    w.origin_distance_mm = along * mm_per_px;
    w.origin_horizontal_mm = std::abs((to_point(branch.points[m]) - origin).dot(h)) * mm_per_px;
    const std::size_t base = from_front ? a : b, tip = from_front ? b : a;
    w.base_end = to_image(branch.points[base]);
    w.tip_end = to_image(branch.points[tip]);
    w.heading_deg = heading_deg(to_point(branch.points[tip]) - to_point(branch.points[base]));
    w.has_position = local.has_position;
    w.position_m = local.position_m;
    w.base_end_m = from_front ? local.first_m : local.last_m;
    w.tip_end_m = from_front ? local.last_m : local.first_m;
    const point3f axis = w.tip_end_m - w.base_end_m;
    const float axis_length = axis.norm();
    w.axis_m = axis_length > 0 ? point3f(axis / axis_length) : point3f::Zero();
    PERCH_TRY(out.push_back(w));
  }
  return {};
}

}  // namespace perch
