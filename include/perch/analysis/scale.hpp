// SPDX-License-Identifier: BSL-1.0
/// \file
/// Scale policies: how many millimetres one pixel spans. Fixed, from the trunk prior (the
/// reference prototype's rule), or from depth and pinhole intrinsics per window (the paper's
/// future work: RGB-D calibration). With depth, sites also get a 3-D camera-frame position.
#pragma once

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <span>

#include "perch/core/geometry.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/mask.hpp"
#include "perch/core/result.hpp"
#include "perch/core/workspace.hpp"

namespace perch {

/// What a scale policy may read: the image size and the largest distance-transform value on the
/// tree (the trunk's half-width, in px), plus scratch memory.
struct scale_context {
  int width = 0;                ///< input image width (px)
  int height = 0;               ///< input image height (px)
  float max_distance_px = 0;    ///< largest Euclidean distance to background on the mask
  std::span<const pixel> sample{};  ///< tree pixels to sample (e.g. skeleton pixels)
  pixel offset{};                   ///< added to `sample` points to get image coordinates
  std::span<float> scratch{};   ///< at least `sample.size()` floats
};

/// A window's own scale, and its camera-frame position when depth is known: of its middle
/// point, and of its first and last points (in the order the window's points are given).
struct local_scale {
  float mm_per_px = 0;
  bool has_position = false;
  point3f position_m = point3f::Zero();
  point3f first_m = point3f::Zero();
  point3f last_m = point3f::Zero();
};

/// A scale policy: a global mm/px for the whole tree (pruning lengths, window lengths) and a
/// local one per window. Concept checked in `find_perch`'s signature.
/// `local(window, offset, middle, scratch, global)` gets the window's centreline points (plus
/// `offset` = image coordinates), its middle point in image coordinates, scratch of at least
/// `window.size()` floats, and the global scale to fall back on.
/// `rescaled(factor, ws)` is the same policy for the image reduced by `factor` ∈ (0, 1]
/// (`perch_options::downscale`; workspace memory for what it resamples): required, so that a
/// policy that cannot be reduced fails at compile time, not at run time with a downscale.
template <class S>
concept ScalePolicy = requires(const S& s, const scale_context& c, std::span<const pixel> window,
                               pixel p, std::span<float> scratch, workspace& ws) {
  { S::name } -> std::convertible_to<std::string_view>;
  { s.validate(c) } noexcept -> std::same_as<status>;
  { s.global_mm_per_px(c) } noexcept -> std::same_as<result<float>>;
  { s.local(window, p, p, scratch, float{}) } noexcept -> std::same_as<local_scale>;
  { s.rescaled(float{}, ws) } noexcept -> std::same_as<result<S>>;
};

/// How well a scale is known, relative (0.1: the true scale lies within ±10 % of the one
/// given). Every rule stated in millimetres then holds at both ends of that range (a gap, the
/// grasp minimum and the drone's width at the fine end, the grasp maximum and the twig limit at
/// the coarse end): a scale that is off makes perch refuse more, never perch where it should
/// not. Valid in [0, 0.5).
[[nodiscard]] constexpr bool valid_scale_uncertainty(float u) noexcept {
  return u >= 0.0f && u < 0.5f;  // false for NaN
}

/// The `relative_uncertainty` of a scale policy; 0 for a policy without one.
template <class S>
[[nodiscard]] constexpr float scale_uncertainty(const S& s) noexcept {
  if constexpr (requires { { s.relative_uncertainty } -> std::convertible_to<float>; })
    return s.relative_uncertainty;
  else
    return 0.0f;
}

/// A known, constant scale (e.g. from a calibrated camera at a known distance).
struct fixed_scale {
  static constexpr std::string_view name = "fixed";
  float mm_per_px = 1.0f;
  float relative_uncertainty = 0.0f;  ///< see `scale_uncertainty`; 0: known exactly

  [[nodiscard]] status validate(const scale_context&) const noexcept {
    if (!(std::isfinite(mm_per_px) && mm_per_px > 0))
      return fail(errc::invalid_parameter, "fixed_scale.mm_per_px");
    if (!valid_scale_uncertainty(relative_uncertainty))
      return fail(errc::invalid_parameter, "fixed_scale.relative_uncertainty");
    return {};
  }
  [[nodiscard]] result<float> global_mm_per_px(const scale_context&) const noexcept {
    return mm_per_px;
  }
  [[nodiscard]] local_scale local(std::span<const pixel>, pixel, pixel, std::span<float>,
                                  float global) const noexcept {
    return {global, false, point3f::Zero(), point3f::Zero(), point3f::Zero()};
  }
  /// The same scale for the image reduced by `factor` (see `find_perch`'s downscale).
  [[nodiscard]] result<fixed_scale> rescaled(float factor, workspace&) const noexcept {
    return fixed_scale{mm_per_px / factor, relative_uncertainty};
  }
};

/// The trunk prior: the widest point of the tree is its trunk, of diameter
/// `trunk_diameter_mm` [180 mm] (the reference prototype's calibration) give or take
/// `relative_uncertainty` [10 %]. Diameter at the widest point = 2·d_max − 1 px.
/// A prior is a guess: trunks of one stand differ by tens of per cent, and a scale read 11 %
/// too coarse made every eighth perch of the synthetic population unsafe (gaps read wider than
/// they are) where ±10 % made none (docs/accuracy-log.md, session 15). State the trunk you
/// expect and how well you know it; a wider range refuses more.
struct trunk_prior {
  static constexpr std::string_view name = "trunk-prior";
  float trunk_diameter_mm = 180.0f;
  float relative_uncertainty = 0.1f;  ///< how far the trunk may be from `trunk_diameter_mm`

  [[nodiscard]] status validate(const scale_context&) const noexcept {
    if (!(std::isfinite(trunk_diameter_mm) && trunk_diameter_mm > 0))
      return fail(errc::invalid_parameter, "trunk_prior.trunk_diameter_mm");
    if (!valid_scale_uncertainty(relative_uncertainty))
      return fail(errc::invalid_parameter, "trunk_prior.relative_uncertainty");
    return {};
  }
  [[nodiscard]] result<float> global_mm_per_px(const scale_context& c) const noexcept {
    const float widest_px = 2.0f * c.max_distance_px - 1.0f;
    if (!(widest_px > 0)) return fail(errc::empty_image, "trunk_prior: no tree pixels");
    return trunk_diameter_mm / widest_px;
  }
  [[nodiscard]] local_scale local(std::span<const pixel>, pixel, pixel, std::span<float>,
                                  float global) const noexcept {
    return {global, false, point3f::Zero(), point3f::Zero(), point3f::Zero()};
  }
  /// Measured on whatever image it is given: unchanged by downscaling.
  [[nodiscard]] result<trunk_prior> rescaled(float, workspace&) const noexcept { return *this; }
};

/// Pinhole intrinsics in pixels of the (mask) image.
struct pinhole {
  float fx = 0, fy = 0, cx = 0, cy = 0;
  [[nodiscard]] status validate() const noexcept {
    for (const float v : {fx, fy, cx, cy})
      if (!std::isfinite(v)) return fail(errc::invalid_parameter, "pinhole");
    if (!(fx > 0 && fy > 0)) return fail(errc::invalid_parameter, "pinhole.fx/fy");
    return {};
  }
  /// The camera-frame point (m) of image point `p` at depth `z_m` along the optical axis:
  /// X = (u − cx)·Z/fx, Y = (v − cy)·Z/fy.
  [[nodiscard]] point3f back_project(point2f p, float z_m) const noexcept {
    return point3f((p.x() - cx) * z_m / fx, (p.y() - cy) * z_m / fy, z_m);
  }
  /// The image point of camera-frame point `q` (its z > 0): `back_project`'s inverse,
  /// u = cx + fx·X/Z, v = cy + fy·Y/Z.
  [[nodiscard]] point2f project(const point3f& q) const noexcept {
    return point2f(cx + fx * q.x() / q.z(), cy + fy * q.y() / q.z());
  }
};

/// Scale from a depth image (millimetres along the optical axis, 0 = invalid) registered to
/// the mask, and pinhole intrinsics: mm/px = Z / f at the median valid depth of each window's
/// centreline pixels; the site's position is back-projected at it (`pinhole::back_project`,
/// metres). The window's two ends are back-projected at the median depth of their own quarter
/// of the window (the window's when that quarter has none), so the branch's axis between them
/// leans toward or away from the camera as the limb does.
struct depth_scale {
  static constexpr std::string_view name = "depth";
  image_view<const std::uint16_t> depth_mm{};
  pinhole intrinsics{};
  float relative_uncertainty = 0.0f;  ///< the depth's and focal length's, see `scale_uncertainty`

  [[nodiscard]] status validate(const scale_context& c) const noexcept {
    PERCH_TRY(validate_non_empty(depth_mm));
    PERCH_TRY(intrinsics.validate());
    if (!valid_scale_uncertainty(relative_uncertainty))
      return fail(errc::invalid_parameter, "depth_scale.relative_uncertainty");
    if (depth_mm.width() != c.width || depth_mm.height() != c.height)
      return fail(errc::size_mismatch, "depth_scale.depth_mm vs mask");
    return {};
  }
  [[nodiscard]] result<float> global_mm_per_px(const scale_context& c) const noexcept {
    const float z = median_depth(c.sample, c.offset, c.scratch);
    if (!(z > 0)) return fail(errc::no_valid_depth, "depth_scale: no valid depth on the tree");
    return z / focal();
  }
  [[nodiscard]] local_scale local(std::span<const pixel> window, pixel offset, pixel middle,
                                  std::span<float> scratch, float global) const noexcept {
    const float z = median_depth(window, offset, scratch);
    if (!(z > 0)) return {global, false, point3f::Zero(), point3f::Zero(), point3f::Zero()};
    const std::size_t quarter = std::max<std::size_t>(1, window.size() / 4);
    auto end_at = [&](std::span<const pixel> part, pixel end) {
      const float z_end = median_depth(part, offset, scratch);
      return back_project({end.x + offset.x, end.y + offset.y}, z_end > 0 ? z_end : z);
    };
    return {z / focal(), true, back_project(middle, z),
            end_at(window.first(quarter), window.front()),
            end_at(window.last(quarter), window.back())};
  }

  /// The policy for the image reduced by `factor`: depth sampled at each reduced pixel's
  /// centre (nearest input pixel; workspace memory) and intrinsics scaled to match.
  [[nodiscard]] result<depth_scale> rescaled(float factor, workspace& ws) const noexcept {
    if (factor == 1.0f) return *this;
    const int w = scaled_extent(depth_mm.width(), factor);
    const int h = scaled_extent(depth_mm.height(), factor);
    auto buffer = ws.allocate<std::uint16_t>(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
    PERCH_TRY(all_ok(buffer));
    image_view<std::uint16_t> reduced(buffer->data(), w, h);
    auto source = [&](int a, int limit) {
      const auto v = static_cast<int>((static_cast<float>(a) + 0.5f) / factor);
      return std::min(limit - 1, v);
    };
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        reduced(x, y) = depth_mm(source(x, depth_mm.width()), source(y, depth_mm.height()));
    depth_scale out = *this;
    out.depth_mm = reduced;
    out.intrinsics = {intrinsics.fx * factor, intrinsics.fy * factor,
                      (intrinsics.cx + 0.5f) * factor - 0.5f, (intrinsics.cy + 0.5f) * factor - 0.5f};
    return out;
  }

 private:
  [[nodiscard]] float focal() const noexcept { return 0.5f * (intrinsics.fx + intrinsics.fy); }
  /// The camera-frame point (m) of image pixel `p` at depth `z_mm`.
  [[nodiscard]] point3f back_project(pixel p, float z_mm) const noexcept {
    return intrinsics.back_project(to_point(p), z_mm / 1000.0f);
  }
  /// Median of the valid depths at `points` (0 when none); `scratch` ≥ points.size().
  [[nodiscard]] float median_depth(std::span<const pixel> points, pixel offset,
                                   std::span<float> scratch) const noexcept {
    std::size_t n = 0;
    for (const pixel q : points) {
      const pixel p{q.x + offset.x, q.y + offset.y};
      if (!depth_mm.contains(p.x, p.y) || n >= scratch.size()) continue;
      const std::uint16_t z = depth_mm(p.x, p.y);
      if (z != 0) scratch[n++] = static_cast<float>(z);
    }
    if (n == 0) return 0.0f;
    const auto mid = scratch.begin() + static_cast<std::ptrdiff_t>(n / 2);
    std::nth_element(scratch.begin(), mid, scratch.begin() + static_cast<std::ptrdiff_t>(n));
    return *mid;
  }
};

}  // namespace perch
