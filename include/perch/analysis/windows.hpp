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

namespace detail {

/// One branch with its per-point profiles in `measure_windows`' scratch: arc length, curvature,
/// slope, the gap to the frame's edge, bend, and `work` (3n floats) for the local scale and the
/// lower tercile; and the look-ups the window steps share.
struct window_branch {
  const branch_geometry& branch;
  std::span<float> arc;
  std::span<float> kappa;
  std::span<float> work;
  std::span<float> slope;
  std::span<float> border_gap;
  std::span<float> bend;

  /// First point with arc ≥ s.
  [[nodiscard]] std::size_t index_at(float s) const noexcept {
    return static_cast<std::size_t>(std::lower_bound(arc.begin(), arc.end(), s) - arc.begin());
  }
  /// Last point with arc ≤ s.
  [[nodiscard]] std::size_t last_at(float s) const noexcept {
    const auto it = std::upper_bound(arc.begin(), arc.end(), s);
    return static_cast<std::size_t>(it - arc.begin()) - 1;
  }
  [[nodiscard]] pixel to_image(pixel p) const noexcept {
    return pixel{p.x + branch.offset.x, p.y + branch.offset.y};
  }
  [[nodiscard]] float diameter_at(std::size_t i) const noexcept {
    return branch.diameter_px.empty() ? diameter_px(branch.radius_px[i]) : branch.diameter_px[i];
  }
};

/// Step 1 of `measure_windows`: the per-point profiles of `branch` (n ≥ 2 points) in `scratch`.
/// Each point's slope and the gap between its outline and the frame's edge (px) are computed
/// once (windows overlap), in the tangents' place, which nothing reads after this.
[[nodiscard]] inline window_branch window_profiles(const branch_geometry& branch,
                                                   float global_mm_per_px, std::span<float> scratch,
                                                   const window_options& options,
                                                   point2f h) noexcept {
  const std::size_t n = branch.points.size();
  window_branch v{branch,
                  scratch.first(n),
                  scratch.subspan(n, n),
                  scratch.subspan(2 * n, 3 * n),
                  scratch.subspan(5 * n, n),
                  scratch.subspan(6 * n, n),
                  scratch.subspan(7 * n, n)};
  std::span<float> tangent_x = v.slope;
  std::span<float> tangent_y = v.border_gap;
  arc_lengths(branch.points, v.arc);
  curvature_profile(branch.points, v.kappa, v.work, options.curvature_at(global_mm_per_px));
  tangent_profile(branch.points, v.arc, branch.radius_px, tangent_x, tangent_y);
  bend_profile(v.arc, tangent_x, tangent_y, 0.5f * options.drone_width_mm / global_mm_per_px,
               v.bend);
  const bool framed = branch.frame_width > 0 && branch.frame_height > 0;
  for (std::size_t i = 0; i < n; ++i) {
    v.slope[i] = slope_to_horizon_deg(point2f(tangent_x[i], tangent_y[i]), h);
    const pixel p = v.to_image(branch.points[i]);
    const int edge = std::min({p.x, p.y, branch.frame_width - 1 - p.x, branch.frame_height - 1 - p.y});
    v.border_gap[i] = framed ? static_cast<float>(edge) - branch.radius_px[i]
                             : std::numeric_limits<float>::max();
  }
  return v;
}

/// A window cut from a branch: points `a`..`b`, its scale and local measures.
struct window_cut {
  std::size_t a = 0;
  std::size_t b = 0;
  float mm_per_px = 0;
  local_scale local{};
};

/// Step 2 of `measure_windows`: cuts the window starting at arc `start` (which fits in the
/// branch at the global scale) into `cut`; false when it holds no points or, at its local
/// scale, no longer fits. Local scale (depth): measured on this window's pixels; the window is
/// then re-cut to one drone width at that scale and measured again for its position.
template <ScalePolicy Scale>
[[nodiscard]] bool cut_window(const window_branch& v, const Scale& scale, float start,
                              float global_mm_per_px, float drone_width_mm,
                              window_cut& cut) noexcept {
  const float total_px = v.arc.back();
  float mm_per_px = global_mm_per_px;
  float length_px = drone_width_mm / mm_per_px;
  const std::size_t a = v.index_at(start);
  std::size_t b = v.last_at(start + length_px);
  if (b <= a) return false;
  auto local_at = [&](std::size_t first, std::size_t last) {
    const std::size_t count = last - first + 1;
    return scale.local(v.branch.points.subspan(first, count), v.branch.offset,
                       v.to_image(v.branch.points[(first + last) / 2]),
                       v.work.first(std::min(v.work.size(), count)), global_mm_per_px);
  };
  local_scale local = local_at(a, b);
  if (local.mm_per_px != mm_per_px && local.mm_per_px > 0) {
    mm_per_px = local.mm_per_px;
    length_px = drone_width_mm / mm_per_px;
    if (start + length_px > total_px + 1e-3f) return false;
    b = v.last_at(start + length_px);
    if (b <= a) return false;
    local = local_at(a, b);
    local.mm_per_px = mm_per_px;
  }
  cut = window_cut{a, b, mm_per_px, local};
  return true;
}

/// Step 3: the window's middle point, the one nearest half way along its arc.
[[nodiscard]] inline std::size_t window_middle(const window_branch& v, std::size_t a,
                                               std::size_t b) noexcept {
  const float mid_arc = 0.5f * (v.arc[a] + v.arc[b]);
  std::size_t m = v.index_at(mid_arc);
  if (m > a && mid_arc - v.arc[m - 1] < v.arc[m] - mid_arc) --m;
  return m;
}

/// Step 4: the measures taken over the window's points (curvature, slope, bend, border and
/// diameters, the claw's around the middle `m`). One pass over the points, kept whole: it is
/// the per-point hot loop of the window stage.
inline void measure_window_points(const window_branch& v, const window_cut& cut, std::size_t m,
                                  float claw_width_mm, window_measures& w) noexcept {
  const std::size_t a = cut.a, b = cut.b;
  const float mm_per_px = cut.mm_per_px;
  float kmax = 0;
  float ksum = 0;
  float slope_max = 0, bend_max = 0;
  float border = std::numeric_limits<float>::max();
  float dmin = 1e30f, dmax = 0, dsum = 0, claw_sum = 0;
  float rmax = 0;
  std::size_t claw_count = 0;
  const float claw_half_px = 0.5f * claw_width_mm / mm_per_px;
  for (std::size_t i = a; i <= b; ++i) {
    kmax = std::max(kmax, std::abs(v.kappa[i]));
    slope_max = std::max(slope_max, v.slope[i]);
    bend_max = std::max(bend_max, v.bend[i]);
    border = std::min(border, v.border_gap[i]);
    ksum += std::abs(v.kappa[i]);
    rmax = std::max(rmax, v.branch.radius_px[i]);
    const float d = v.diameter_at(i);
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
    dsum += d;
    if (std::abs(v.arc[i] - v.arc[m]) <= claw_half_px) {
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
      (claw_count > 0 ? claw_sum / static_cast<float>(claw_count) : v.diameter_at(m)) *
      mm_per_px;
  w.slope_max_deg = slope_max;
  w.bend_deg = bend_max;
  w.border_px = border;
  w.radius_max_px = rmax;
}

/// Step 5: the lower tercile (a third of the values are below it) of `value(i)` over the
/// window's points `a`..`b`, selected in `work` (free again once the local scale is measured).
template <typename Value>
[[nodiscard]] float lower_tercile(const window_branch& v, std::size_t a, std::size_t b,
                                  Value value) noexcept {
  const std::span<float> work = v.work;
  const std::size_t low_count = std::min(b - a + 1, work.size());
  for (std::size_t i = 0; i < low_count; ++i) work[i] = value(a + i);
  const auto low_rank = static_cast<std::ptrdiff_t>((low_count - 1) / 3);
  std::nth_element(work.begin(), work.begin() + low_rank,
                   work.begin() + static_cast<std::ptrdiff_t>(low_count));
  return work[static_cast<std::size_t>(low_rank)];
}

/// Step 6: where the window lies toward the branch's origin end (distances from it, base and
/// tip ends, heading) and in space (position, ends and axis from the local scale).
inline void orient_window(const window_branch& v, const window_cut& cut, std::size_t m, point2f h,
                          window_measures& w) noexcept {
  const branch_geometry& branch = v.branch;
  // Origin end, in local coordinates, and arc length measured from it.
  const bool from_front = branch.origin == origin_end::front;
  const point2f origin = to_point(from_front ? branch.points.front() : branch.points.back());
  const float along = from_front ? v.arc[m] : v.arc.back() - v.arc[m];
  w.origin_distance_mm = along * cut.mm_per_px;
  w.origin_horizontal_mm =
      std::abs((to_point(branch.points[m]) - origin).dot(h)) * cut.mm_per_px;
  const std::size_t base = from_front ? cut.a : cut.b, tip = from_front ? cut.b : cut.a;
  w.base_end = v.to_image(branch.points[base]);
  w.tip_end = v.to_image(branch.points[tip]);
  w.heading_deg = heading_deg(to_point(branch.points[tip]) - to_point(branch.points[base]));
  const local_scale& local = cut.local;
  w.has_position = local.has_position;
  w.position_m = local.position_m;
  w.base_end_m = from_front ? local.first_m : local.last_m;
  w.tip_end_m = from_front ? local.last_m : local.first_m;
  const point3f axis = w.tip_end_m - w.base_end_m;
  const float axis_length = axis.norm();
  w.axis_m = axis_length > 0 ? point3f(axis / axis_length) : point3f::Zero();
}

/// The measures of one cut window (steps 3 to 6).
[[nodiscard]] inline window_measures measure_window(const window_branch& v, const window_cut& cut,
                                                    const window_options& options,
                                                    point2f h) noexcept {
  const branch_geometry& branch = v.branch;
  const std::size_t a = cut.a, b = cut.b;
  const std::span<const pixel> pts = branch.points.subspan(a, b - a + 1);
  const std::size_t m = window_middle(v, a, b);
  window_measures w;
  w.limb = branch.limb;
  w.component = branch.component;
  w.first = branch.first_index + static_cast<std::uint32_t>(a);
  w.last = branch.first_index + static_cast<std::uint32_t>(b);
  w.middle = branch.first_index + static_cast<std::uint32_t>(m);
  w.centre = v.to_image(branch.points[m]);
  w.start_px = v.arc[a];
  w.length_px = v.arc[b] - v.arc[a];
  w.mm_per_px = cut.mm_per_px;
  w.slope_deg = slope_to_horizon_deg(to_point(pts.back()) - to_point(pts.front()), h);
  w.slope_fit_deg = fitted_slope_deg(pts, h);
  measure_window_points(v, cut, m, options.claw_width_mm, w);
  w.diameter_low_mm =
      lower_tercile(v, a, b, [&](std::size_t i) { return v.diameter_at(i); }) * cut.mm_per_px;
  w.radius_low_px = lower_tercile(v, a, b, [&](std::size_t i) { return branch.radius_px[i]; });
  w.reversal_mm = reversal_px(pts) * cut.mm_per_px;
  w.grounded = branch.grounded;
  orient_window(v, cut, m, h, w);
  return w;
}

}  // namespace detail

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
  const point2f h = options.camera.horizon();
  const detail::window_branch v = detail::window_profiles(branch, global_mm_per_px, scratch,
                                                          options, h);
  const float total_px = v.arc[n - 1];
  const float stride_px = options.stride_mm / global_mm_per_px;
  for (float start = 0; start < total_px; start += stride_px) {
    if (start + options.drone_width_mm / global_mm_per_px > total_px + 1e-3f) break;
    detail::window_cut cut;
    if (!detail::cut_window(v, scale, start, global_mm_per_px, options.drone_width_mm, cut))
      continue;
    PERCH_TRY(out.push_back(detail::measure_window(v, cut, options, h)));
  }
  return {};
}

}  // namespace perch
