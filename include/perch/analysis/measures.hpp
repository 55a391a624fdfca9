// SPDX-License-Identifier: BSL-1.0
/// \file
/// What perch measures on a stretch of branch centreline (paper table 2): slope to the true
/// horizontal, curvature, diameters, monotonicity; and the per-branch profiles they read.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>

#include "perch/analysis/attitude.hpp"
#include "perch/core/geometry.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/prefetch.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_scan.hpp"

namespace perch {

/// Everything measured on one window (one drone width of branch). Lengths in mm use the
/// window's own scale `mm_per_px`; slopes are against the true horizontal (see `attitude`).
struct window_measures {
  std::int32_t limb = -1;       ///< the limb measured (`perch_result::limbs` in `find_perch`)
  std::int32_t branch = -1;     ///< skeleton-graph edge id under `middle` (-1 if not set)
  std::int32_t component = -1;  ///< connected component (tree) id
  std::uint32_t first = 0;      ///< first centreline point of the window (index in the limb)
  std::uint32_t last = 0;       ///< last centreline point (inclusive)
  std::uint32_t middle = 0;     ///< centreline point at half the window's arc length
  pixel centre{};               ///< that point, in the input image's pixel coordinates
  float start_px = 0;           ///< arc length from the branch's first point to `first`
  float length_px = 0;          ///< arc length of the window
  float mm_per_px = 0;          ///< scale used for this window
  float slope_deg = 0;          ///< |atan2| of the end-point chord, folded into [0°, 90°]
  float slope_fit_deg = 0;      ///< same, from an orthogonal least-squares line fit
  float curvature_max_per_mm = 0;   ///< max |κ| of the smoothed curvature over the window
  float curvature_mean_per_mm = 0;  ///< mean |κ| over the window
  float diameter_min_mm = 0;    ///< minimum of the branch's diameters over the window
  float diameter_max_mm = 0;    ///< maximum diameter over the window
  float diameter_mean_mm = 0;   ///< mean diameter over the window
  /// Lower tercile of the diameters over the window (a third of them are below it): the limb's
  /// width under outline noise that only adds to it (bumps, spurs, leaves, a twig's base), which
  /// inflates the mean. 0: not measured.
  float diameter_low_mm = 0;
  float claw_diameter_mm = 0;   ///< mean diameter over the central claw region
  /// Largest and lower-tercile radius (px: the centreline's distance to the background) over
  /// the window. One limb tapers gently under a drone's width; where the radius swells well
  /// above its lower tercile the mask there is wider than this limb: another limb lying along
  /// or merging into it, or the crotch of a fork (`one_limb`). 0: not measured.
  float radius_max_px = 0;
  float radius_low_px = 0;
  float reversal_mm = 0;        ///< largest step back along the chord (0 for a monotonic window)
  /// Largest slope (°, [0, 90]) of the limb's local tangent (`tangent_profile`) at any point of
  /// the window: a limb that is level on average but steep at one end is not a level perch.
  float slope_max_deg = 0;
  /// Largest change of heading (°) between the limb's tangents half a drone width before and
  /// after any point of the window, clipped at the analysed stretch's ends (`bend_profile`): a
  /// kink or a tight curve under or beside the drone's body.
  float bend_deg = 0;
  /// Smallest gap (px, analysed frame) between the limb's outline under the window and the
  /// frame's edge: a limb cut by the frame is not known beyond it, and a mask's last pixels
  /// are the least reliable.
  float border_px = std::numeric_limits<float>::max();
  /// The window's piece of mask holds something up (`grounded_components`): it reaches the
  /// bottom of the frame or is the main tree. A detached piece is never a perch.
  bool grounded = true;
  float origin_distance_mm = 0;    ///< arc length from the branch's origin (toward the trunk)
  float origin_horizontal_mm = 0;  ///< horizontal part of origin → centre (bending lever arm)
  /// The window's end toward the limb's origin (the trunk side) and its end toward the tip:
  /// centreline points, in the input image's pixel coordinates.
  pixel base_end{};
  pixel tip_end{};
  /// The branch's direction in the image, from `base_end` to `tip_end`: degrees from the image's
  /// +x axis, counter-clockwise as seen with the image's y axis pointing up, in (−180°, 180°]
  /// (0°: the branch runs out to the right, 90°: up the image, ±180°: to the left). Unlike
  /// `slope_deg` it is signed and not folded, and it ignores the camera's roll: a drone yaws to
  /// it in the image. Undefined (0) for a window of one point.
  float heading_deg = 0;
  point3f position_m = point3f::Zero();  ///< camera-frame position when depth is known
  point3f base_end_m = point3f::Zero();  ///< camera-frame position of `base_end` (with depth)
  point3f tip_end_m = point3f::Zero();   ///< camera-frame position of `tip_end` (with depth)
  /// Unit vector from `base_end_m` to `tip_end_m`: the branch's axis in 3-D (with depth).
  point3f axis_m = point3f::Zero();
  bool has_position = false;  ///< whether the camera-frame positions and axis are set
};

/// The window `m` read at `k` times its scale (its pixels unchanged): every length in mm
/// times `k`, curvature per mm divided by it. The ranking reads a window at both ends of its
/// scale's uncertainty (`scale_uncertainty`) with this.
[[nodiscard]] inline window_measures at_scale(window_measures m, float k) noexcept {
  m.mm_per_px *= k;
  m.curvature_max_per_mm /= k;
  m.curvature_mean_per_mm /= k;
  for (float* mm : {&m.diameter_min_mm, &m.diameter_max_mm, &m.diameter_mean_mm,
                    &m.diameter_low_mm, &m.claw_diameter_mm, &m.reversal_mm,
                    &m.origin_distance_mm, &m.origin_horizontal_mm})
    *mm *= k;
  return m;
}

/// Options of the curvature estimate (paper table 2: central differences + moving average).
struct curvature_options {
  /// Central-difference half-step and smoothing half-width, in px (≥ 1). Digital centrelines
  /// are staircases: a step of several pixels and a moving average keep the estimate on the
  /// branch's shape rather than on its pixel grid (measured: on digital lines the noise is
  /// 0.013 px⁻¹ at 3 px, 0.0016 px⁻¹ at 8 px; on arcs the mean stays within 2 % of 1/r).
  int stencil_px = 8;
};

/// Cumulative arc length at every point of a centreline, `arc_px[0] = 0`: the sum of chords
/// between every `chord_points`-th point, each chord shared among the steps it spans in
/// proportion to their lengths. Counting the 8-connected steps of a staircase as 1 or √2
/// overestimates the line it digitises by up to 8 % (at 22.5°; 5 % on average over directions),
/// so a window of that many steps would be shorter than the drone; a chord over 8 pixels is
/// within a few hundredths of a pixel of the length of a straight line or of a gentle arc.
/// `arc_px.size()` must equal `points.size()`. Complexity O(n).
inline void arc_lengths(std::span<const pixel> points, std::span<float> arc_px,
                        std::size_t chord_points = 8) noexcept {
  PERCH_ASSERT(arc_px.size() == points.size(), "arc_lengths: size mismatch");
  const std::size_t n = points.size();
  if (n == 0) return;
  auto distance = [&](std::size_t i, std::size_t j) {
    const float dx = static_cast<float>(points[j].x - points[i].x);
    const float dy = static_cast<float>(points[j].y - points[i].y);
    return std::sqrt(dx * dx + dy * dy);
  };
  const std::size_t k = chord_points > 0 ? chord_points : 1;
  arc_px[0] = 0;
  for (std::size_t a = 0; a + 1 < n;) {
    const std::size_t b = std::min(a + k, n - 1);
    float steps = 0;
    for (std::size_t i = a + 1; i <= b; ++i) {
      steps += distance(i - 1, i);
      arc_px[i] = steps;
    }
    const float share = steps > 0 ? distance(a, b) / steps : 0.0f;
    for (std::size_t i = a + 1; i <= b; ++i) arc_px[i] = arc_px[a] + arc_px[i] * share;
    a = b;
  }
}

namespace detail {

/// Index `i` clamped to [0, `last`].
[[nodiscard]] inline std::size_t clamped_index(std::ptrdiff_t i, std::ptrdiff_t last) noexcept {
  return static_cast<std::size_t>(std::clamp<std::ptrdiff_t>(i, 0, last));
}

/// Step 1 of `curvature_profile`: moving average of positions (window 2h+1, clamped) into
/// `sx`, `sy`, by running sums of the integer coordinates (exact).
inline void smooth_positions(std::span<const pixel> points, std::ptrdiff_t h, std::span<float> sx,
                             std::span<float> sy) noexcept {
  const std::size_t n = points.size();
  const auto last = static_cast<std::ptrdiff_t>(n) - 1;
  const auto count = static_cast<float>(2 * h + 1);
  std::int64_t ax = 0;
  std::int64_t ay = 0;
  for (std::ptrdiff_t k = -h; k <= h; ++k) {
    ax += points[clamped_index(k, last)].x;
    ay += points[clamped_index(k, last)].y;
  }
  for (std::size_t i = 0; i < n; ++i) {
    sx[i] = static_cast<float>(ax) / count;
    sy[i] = static_cast<float>(ay) / count;
    const auto c = static_cast<std::ptrdiff_t>(i);
    const pixel leaving = points[clamped_index(c - h, last)];
    const pixel entering = points[clamped_index(c + h + 1, last)];
    ax += entering.x - leaving.x;
    ay += entering.y - leaving.y;
  }
}

/// Step 2: κ at every point of the smoothed positions `sx`, `sy`, by central differences of
/// step `h` (clamped at the ends).
inline void curvature_of_smoothed(std::span<const float> sx, std::span<const float> sy,
                                  std::ptrdiff_t h, std::span<float> curvature_px) noexcept {
  const std::size_t n = sx.size();
  const auto last = static_cast<std::ptrdiff_t>(n) - 1;
  for (std::size_t i = 0; i < n; ++i) {
    const auto c = static_cast<std::ptrdiff_t>(i);
    const std::size_t lo = clamped_index(c - h, last);
    const std::size_t hi = clamped_index(c + h, last);
    const auto span = static_cast<float>(hi - lo);
    if (span <= 0) {
      curvature_px[i] = 0;
      continue;
    }
    const float a = static_cast<float>(i - lo);
    const float b = static_cast<float>(hi - i);
    // First and second derivatives for (possibly uneven, at the ends) steps a and b.
    const float dx = (sx[hi] - sx[lo]) / span;
    const float dy = (sy[hi] - sy[lo]) / span;
    float ddx = 0;
    float ddy = 0;
    if (a > 0 && b > 0) {
      ddx = 2.0f * (b * sx[lo] - span * sx[i] + a * sx[hi]) / (a * b * span);
      ddy = 2.0f * (b * sy[lo] - span * sy[i] + a * sy[hi]) / (a * b * span);
    }
    const float speed2 = dx * dx + dy * dy;
    curvature_px[i] = speed2 > 0 ? (dx * ddy - dy * ddx) / (speed2 * std::sqrt(speed2)) : 0.0f;
  }
}

/// Step 3: moving average of κ (window 2h+1, clamped), `copy` (n floats) holding κ's copy.
/// Each mean adds its window's terms in order; away from the ends four neighbouring means are
/// summed side by side (independent chains).
inline void smooth_curvature(std::span<float> curvature_px, std::ptrdiff_t h,
                             std::span<float> copy) noexcept {
  const std::size_t n = curvature_px.size();
  const auto last = static_cast<std::ptrdiff_t>(n) - 1;
  const auto count = static_cast<float>(2 * h + 1);
  std::span<float> sx = copy.first(n);
  // The mean of sx over [c − h, c + h] with indices clamped, terms added in that order.
  auto clamped_mean = [&](std::size_t i) {
    const auto c = static_cast<std::ptrdiff_t>(i);
    float acc = 0;
    std::ptrdiff_t j = c - h;
    for (; j < 0; ++j) acc += sx[0];
    for (; j <= std::min(c + h, last); ++j) acc += sx[static_cast<std::size_t>(j)];
    for (; j <= c + h; ++j) acc += sx[static_cast<std::size_t>(last)];
    return acc / count;
  };
  std::copy(curvature_px.begin(), curvature_px.end(), sx.begin());
  std::size_t i = 0;
  for (; i < n && static_cast<std::ptrdiff_t>(i) < h; ++i) curvature_px[i] = clamped_mean(i);
  for (; static_cast<std::ptrdiff_t>(i) + 3 + h <= last; i += 4) {
    const float* window = sx.data() + (static_cast<std::ptrdiff_t>(i) - h);
    float a0 = 0, a1 = 0, a2 = 0, a3 = 0;
    for (std::ptrdiff_t k = 0; k <= 2 * h; ++k) {
      a0 += window[k];
      a1 += window[k + 1];
      a2 += window[k + 2];
      a3 += window[k + 3];
    }
    curvature_px[i] = a0 / count;
    curvature_px[i + 1] = a1 / count;
    curvature_px[i + 2] = a2 / count;
    curvature_px[i + 3] = a3 / count;
  }
  for (; i < n; ++i) curvature_px[i] = clamped_mean(i);
}

}  // namespace detail
/// Signed curvature κ (1/px) at every point of a centreline:
/// κ = (ẋÿ − ẏẍ)/(ẋ² + ẏ²)^{3/2} (paper table 2), derivatives by central differences of step
/// `stencil_px` over positions first smoothed by a moving average of half-width `stencil_px`,
/// then κ itself smoothed by the same moving average. Indices are clamped at the ends.
/// `scratch` needs 2·n floats. Complexity O(n).
inline void curvature_profile(std::span<const pixel> points, std::span<float> curvature_px,
                              std::span<float> scratch, curvature_options options = {}) noexcept {
  const std::size_t n = points.size();
  PERCH_ASSERT(curvature_px.size() == n && scratch.size() >= 2 * n, "curvature_profile: sizes");
  if (n == 0) return;
  const std::ptrdiff_t h = std::max(1, options.stencil_px);
  std::span<float> sx = scratch.first(n);
  std::span<float> sy = scratch.subspan(n, n);
  detail::smooth_positions(points, h, sx, sy);
  detail::curvature_of_smoothed(sx, sy, h, curvature_px);
  detail::smooth_curvature(curvature_px, h, sx);  // reuse sx as the copy
}

/// Unit tangent of a centreline at every point, oriented from the first point to the last: the
/// principal axis (orthogonal least squares: the scatter matrix's leading eigenvector, in closed
/// form) of the points within arc length h of it, h = max(its radius, `min_half_arc_px`), the
/// stretch clipped at the polyline's ends. Over about a radius a limb's axis is straight, while a skeleton's
/// pixel steps turn by 45° at a time and a bulge of the outline (a fork's crotch) shifts only a
/// few of its points: the fit reads the limb, not the pixels.
/// `arc_px` from `arc_lengths`; all spans have `points.size()` entries. Complexity O(n): the
/// sums slide along with the stretch.
inline void tangent_profile(std::span<const pixel> points, std::span<const float> arc_px,
                            std::span<const float> radius_px, std::span<float> tangent_x,
                            std::span<float> tangent_y, float min_half_arc_px = 4.0f) noexcept {
  const std::size_t n = points.size();
  PERCH_ASSERT(arc_px.size() == n && radius_px.size() == n && tangent_x.size() == n &&
                   tangent_y.size() == n,
               "tangent_profile: sizes");
  if (n == 0) return;
  // Sums of x, y, x², xy, y² over the points in [a, b], from running sums relative to the
  // first point (exact in double for any image size), so each fit costs O(1).
  struct moments {
    double x = 0, y = 0, xx = 0, xy = 0, yy = 0;
  };
  const pixel origin = points[0];
  auto add = [&](moments& m, std::size_t k, double sign) {
    const double x = points[k].x - origin.x;
    const double y = points[k].y - origin.y;
    m.x += sign * x;
    m.y += sign * y;
    m.xx += sign * x * x;
    m.xy += sign * x * y;
    m.yy += sign * y * y;
  };
  moments window;
  std::size_t lo = 0, hi = 0;  // the points [lo, hi) are in `window`
  std::size_t first = 0, end = 0;  // the points within h of arc: [first, end)
  for (std::size_t i = 0; i < n; ++i) {
    const float h = std::max(radius_px[i], min_half_arc_px);
    // The radius varies slowly along a limb, so both bounds move a step or two either way.
    while (first > 0 && arc_px[first - 1] >= arc_px[i] - h) --first;
    while (arc_px[first] < arc_px[i] - h) ++first;
    while (end > 0 && arc_px[end - 1] > arc_px[i] + h) --end;
    while (end < n && arc_px[end] <= arc_px[i] + h) ++end;
    const std::size_t a = std::min(first, i > 0 ? i - 1 : i);
    const std::size_t b = std::max(end, std::min(i + 2, n));
    // Slide the window to [a, b): usually a step or two at each end.
    if (a >= hi || b <= lo) {
      window = {};
      lo = hi = a;
    }
    while (lo > a) add(window, --lo, 1.0);
    while (lo < a) add(window, lo++, -1.0);
    while (hi < b) add(window, hi++, 1.0);
    while (hi > b) add(window, --hi, -1.0);
    const auto count = static_cast<double>(b - a);
    const double mx = window.x / count, my = window.y / count;
    const double sxx = window.xx - count * mx * mx;
    const double sxy = window.xy - count * mx * my;
    const double syy = window.yy - count * my * my;
    const point2f axis = principal_axis(sxx, sxy, syy);
    const bool isotropic = axis.x() == 0 && axis.y() == 0;  // a lone point: any axis
    float tx = isotropic ? 1.0f : axis.x();
    float ty = isotropic ? 0.0f : axis.y();
    const auto cx = static_cast<float>(points[b - 1].x - points[a].x);
    const auto cy = static_cast<float>(points[b - 1].y - points[a].y);
    if (tx * cx + ty * cy < 0) {
      tx = -tx;
      ty = -ty;
    }
    tangent_x[i] = tx;
    tangent_y[i] = ty;
  }
}

/// At every point of a centreline, the angle (°, [0, 180]) between its tangents (from
/// `tangent_profile`) at arc length `reach_px` before and after it, each clipped to the
/// polyline's ends: how much the limb turns over a drone's width around that point.
/// Complexity O(n).
inline void bend_profile(std::span<const float> arc_px, std::span<const float> tangent_x,
                         std::span<const float> tangent_y, float reach_px,
                         std::span<float> bend_deg) noexcept {
  const std::size_t n = arc_px.size();
  PERCH_ASSERT(tangent_x.size() == n && tangent_y.size() == n && bend_deg.size() == n,
               "bend_profile: sizes");
  std::size_t back = 0, ahead = 0;
  for (std::size_t i = 0; i < n; ++i) {
    while (back + 1 < n && arc_px[back + 1] <= arc_px[i] - reach_px) ++back;
    while (ahead + 1 < n && arc_px[ahead] < arc_px[i] + reach_px) ++ahead;
    const float dot = std::clamp(
        tangent_x[back] * tangent_x[ahead] + tangent_y[back] * tangent_y[ahead], -1.0f, 1.0f);
    bend_deg[i] = std::acos(dot) * 180.0f / std::numbers::pi_v<float>;
  }
}

/// Slope (°) of the orthogonal least-squares line through `points` against horizon `h`
/// (total least squares: the principal axis of the points' covariance [[a, b], [b, c]], whose
/// angle is ½·atan2(2b, a − c) in closed form for a symmetric 2 × 2 matrix; a general
/// eigensolver would cost every including file seconds of compile time).
[[nodiscard]] inline float fitted_slope_deg(std::span<const pixel> points, point2f h) noexcept {
  if (points.size() < 2) return 0.0f;
  double mx = 0, my = 0;
  for (const pixel p : points) {
    mx += p.x;
    my += p.y;
  }
  const auto n = static_cast<double>(points.size());
  mx /= n;
  my /= n;
  double a = 0, b = 0, c = 0;
  for (const pixel p : points) {
    const double dx = p.x - mx;
    const double dy = p.y - my;
    a += dx * dx;
    b += dx * dy;
    c += dy * dy;
  }
  const double angle = 0.5 * std::atan2(2.0 * b, a - c);
  const point2f axis(static_cast<float>(std::cos(angle)), static_cast<float>(std::sin(angle)));
  return slope_to_horizon_deg(axis, h);
}

/// Largest step backwards (px) along the chord from `points.front()` to `points.back()`: the
/// window "reverses" when a point lies behind the furthest point reached so far. 0 for a
/// monotonic stretch (the paper's branch-reversal filter).
[[nodiscard]] inline float reversal_px(std::span<const pixel> points) noexcept {
  if (points.size() < 3) return 0.0f;
  const point2f a = to_point(points.front());
  point2f chord = to_point(points.back()) - a;
  const float norm = chord.norm();
  if (norm <= 0) return 0.0f;
  chord /= norm;
  float furthest = 0;
  float worst = 0;
  for (const pixel p : points) {
    const float t = (to_point(p) - a).dot(chord);
    furthest = std::max(furthest, t);
    worst = std::max(worst, furthest - t);
  }
  return worst;
}

/// Diameter (px) at a skeleton point whose distance to the nearest background pixel centre is
/// `d` px: 2·d − 1 (DESIGN.md "Width"). Exact for axis-aligned strips of an odd pixel width;
/// on real outlines it reads low (see `cross_section_diameters`, which perch measures with).
[[nodiscard]] constexpr float diameter_px(float d) noexcept {
  return d > 0.5f ? 2.0f * d - 1.0f : 0.0f;
}

/// Diameter (px) of the mask's cross-section at every point of a centreline.
///
/// At point i the normal is perpendicular to the chord from point i − k to point i + k
/// (k = `normal_half_span`, clamped to the polyline). The cross-section is walked from the
/// point's pixel centre along both directions of the normal in ¼ px steps, sampling the nearest
/// pixel (outside the image is background); each side's edge lies halfway between the last tree
/// sample and the first background one, and is capped at d + 1.5 px (d = `radius_px[i]`, the
/// distance to the nearest background pixel centre), since a longer walk has run into a limb or
/// twig attached across the branch. The diameter is the sum of both sides.
///
/// Why not 2·d − 1: a limb of width w whose outline is sampled at pixel centres (any mask) has a
/// background pixel centre 0–1 px beyond its edge, and its skeleton lies up to ½ px off its
/// axis, so 2·d − 1 is exact only for odd pixel widths of axis-aligned strips and reads low
/// elsewhere. Measured on strips of random width (8–18 px) and sub-pixel position at 0°–45°:
/// 2·d − 1 is off by −0.57 to −1.04 px on average (rms 0.73–1.09 px); this cross-section by
/// −0.09 to +0.16 px (rms 0.41–0.58 px). Near the claw's smallest diameter that is the
/// difference between a branch that fits and one that does not.
/// `radius_px` and `diameter_px` have `points.size()` entries; `radius_px[i]` must be the
/// distance to the nearest background pixel centre (the walk skips the samples nearer than that,
/// which are tree). Complexity: O(points), about 9 samples per side.
template <BinaryView Mask>
void cross_section_diameters(const Mask& mask, std::span<const pixel> points,
                             std::span<const float> radius_px, std::span<float> diameter_px,
                             int normal_half_span = 4) noexcept {
  PERCH_ASSERT(radius_px.size() == points.size() && diameter_px.size() == points.size(),
               "cross_section_diameters: sizes");
  const auto n = static_cast<std::ptrdiff_t>(points.size());
  const std::ptrdiff_t k = std::max(1, normal_half_span);
  constexpr float step = 0.25f;
  // On a large mask, the edges of the cross-section eight points on are fetched ahead (where
  // they lie if the normal there is about this one's, 1.2 d out), each in rows of its own.
  constexpr std::ptrdiff_t ahead = 8;
  const bool fetch_ahead =
      static_cast<std::size_t>(mask.width()) * static_cast<std::size_t>(mask.height()) >=
      detail::fetch_ahead_from;
  // The chord from point i − k to point i + k (clamped to the polyline).
  auto chord_at = [&](std::ptrdiff_t i) {
    const pixel lo = points[static_cast<std::size_t>(std::max<std::ptrdiff_t>(0, i - k))];
    const pixel hi = points[static_cast<std::size_t>(std::min(n - 1, i + k))];
    return point2f(static_cast<float>(hi.x - lo.x), static_cast<float>(hi.y - lo.y));
  };
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (fetch_ahead && i + ahead < n) {
      const pixel a = points[static_cast<std::size_t>(i + ahead)];
      const float reach = 1.2f * radius_px[static_cast<std::size_t>(i + ahead)];
      const point2f ch = chord_at(i + ahead);
      const float l1 = std::abs(ch.x()) + std::abs(ch.y());  // ≥ its length: inside, at worst
      if (l1 > 0) {
        for (const float side : {reach / l1, -reach / l1}) {
          const int x = std::clamp<int>(a.x - static_cast<int>(side * ch.y()), 0, mask.width() - 1);
          const int y = std::clamp<int>(a.y + static_cast<int>(side * ch.x()), 0, mask.height() - 1);
          detail::prefetch(detail::row_pointer(mask, y) + x);
        }
      }
    }
    const pixel c = points[static_cast<std::size_t>(i)];
    const float d = radius_px[static_cast<std::size_t>(i)];
    const point2f chord = chord_at(i);
    const float len = chord.norm();
    if (!(len > 0) || !(d > 0.5f)) {  // a lone point: no direction to measure across
      diameter_px[static_cast<std::size_t>(i)] = perch::diameter_px(d);
      continue;
    }
    const point2f normal(-chord.y() / len, chord.x() / len);
    const float cap = d + 1.5f;
    // The nearest pixel: floor(v + ½), inline (std::floor is a library call without SSE4.1).
    auto nearest = [](float v) {
      const float u = v + 0.5f;
      const auto whole = static_cast<int>(u);
      return static_cast<float>(whole) > u ? whole - 1 : whole;
    };
    // Samples lie within cap of c: when that square is inside the view, none needs a bounds test.
    const float reach = cap + 1.0f;
    const bool within = static_cast<float>(c.x) >= reach && static_cast<float>(c.y) >= reach &&
                        static_cast<float>(mask.width() - 1 - c.x) >= reach &&
                        static_cast<float>(mask.height() - 1 - c.y) >= reach;
    auto tree_at = [&](float t) {
      const int x = nearest(static_cast<float>(c.x) + t * normal.x());
      const int y = nearest(static_cast<float>(c.y) + t * normal.y());
      return (within || (x >= 0 && y >= 0 && x < mask.width() && y < mask.height())) &&
             static_cast<bool>(mask(x, y));
    };
    // Every pixel centre nearer than d is tree, and a sample's nearest pixel centre is within
    // √2/2 of it: the samples up to d − √2/2 are tree, so the walk starts there (same result,
    // O(1) steps per side instead of O(d)).
    const float inside = step * std::floor(std::max(0.0f, d - 0.7072f) / step);
    auto side = [&](float direction) {
      float t = inside;
      while (t + step <= cap && tree_at(direction * (t + step))) t += step;
      return t + step > cap ? cap : t + 0.5f * step;
    };
    diameter_px[static_cast<std::size_t>(i)] = side(1.0f) + side(-1.0f);
  }
}

}  // namespace perch
