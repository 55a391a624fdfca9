// SPDX-License-Identifier: BSL-1.0
/// \file
/// The camera's motion between two frames, as it moves image points: a projective map
/// (homography) of the previous frame's pixels to the current frame's, built from a 2-D
/// similarity (scale, rotation, shift), from a homography the user's visual odometry gives, or
/// the identity when nothing is known. The tracker predicts its tracks with it.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include <array>
#include <cmath>
#include <numbers>

#include "perch/core/geometry.hpp"

namespace perch {

/// A map of the previous frame's pixel coordinates (x right, y down, input pixels) to the
/// current frame's: p' = H·(x, y, 1), divided by its third coordinate. Row-major 3×3.
struct camera_motion {
  std::array<float, 9> h{1, 0, 0, 0, 1, 0, 0, 0, 1};
  /// The relative standard uncertainty (1σ) of the map's scale: how far the depth ratio it
  /// implies (`perch_tracker` carries a track's depth with it) may be off, 0.002 for 0.2 %.
  /// 0: exact, or not stated (the tracker then allows its `tracker_options::depth_drift`
  /// alone). `motion_estimator` states it.
  float scale_uncertainty = 0;

  /// No motion.
  [[nodiscard]] static constexpr camera_motion identity() noexcept { return {}; }

  /// p' = scale · R(rotation_deg) · p + (tx, ty). A positive rotation turns the picture from
  /// +x toward +y (clockwise on screen, as `attitude::roll_deg`).
  [[nodiscard]] static camera_motion similarity(float scale, float rotation_deg, float tx,
                                                float ty) noexcept {
    const float a = rotation_deg * std::numbers::pi_v<float> / 180.0f;
    const float c = scale * std::cos(a), s = scale * std::sin(a);
    camera_motion m;
    m.h = {c, -s, tx, s, c, ty, 0, 0, 1};
    return m;
  }

  /// A similarity about a centre: points near `centre` move by `shift` after the scale and
  /// rotation about it (how a camera that zooms and rolls about its optical axis moves them).
  [[nodiscard]] static camera_motion similarity_about(point2f centre, float scale,
                                                      float rotation_deg, point2f shift) noexcept {
    camera_motion m = similarity(scale, rotation_deg, 0, 0);
    const point2f moved = m.apply(centre);
    m.h[2] = centre.x() - moved.x() + shift.x();
    m.h[5] = centre.y() - moved.y() + shift.y();
    return m;
  }

  /// Where `p` of the previous frame is in the current one.
  [[nodiscard]] point2f apply(point2f p) const noexcept {
    const float w = h[6] * p.x() + h[7] * p.y() + h[8];
    return {(h[0] * p.x() + h[1] * p.y() + h[2]) / w, (h[3] * p.x() + h[4] * p.y() + h[5]) / w};
  }

  /// The composition: first `first`, then this (their scales' uncertainties added in
  /// quadrature, as independent errors).
  [[nodiscard]] camera_motion after(const camera_motion& first) const noexcept {
    camera_motion out;
    out.scale_uncertainty = std::hypot(scale_uncertainty, first.scale_uncertainty);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) {
        float sum = 0;
        for (int k = 0; k < 3; ++k) sum += h[static_cast<std::size_t>(r * 3 + k)] *
                                           first.h[static_cast<std::size_t>(k * 3 + c)];
        out.h[static_cast<std::size_t>(r * 3 + c)] = sum;
      }
    return out;
  }

  /// Every entry finite, the scale's uncertainty finite and not negative, and the map
  /// invertible and not folding the picture over (the upper 2×2 block's determinant positive,
  /// the projective part not sending a pixel to infinity near the origin): a motion a camera
  /// can make.
  [[nodiscard]] bool valid() const noexcept {
    for (const float v : h)
      if (!std::isfinite(v)) return false;
    if (!(scale_uncertainty >= 0 && std::isfinite(scale_uncertainty))) return false;
    const float det2 = h[0] * h[4] - h[1] * h[3];
    return det2 > 0 && std::isfinite(det2) && h[8] > 0;
  }

  /// The map's local scale at `p` (the square root of its Jacobian's determinant), for
  /// scaling lengths measured there.
  [[nodiscard]] float scale_at(point2f p) const noexcept {
    const point2f o = apply(p), ex = apply(p + point2f(1, 0)), ey = apply(p + point2f(0, 1));
    const point2f a = ex - o, b = ey - o;
    return std::sqrt(std::abs(a.x() * b.y() - a.y() * b.x()));
  }
};

}  // namespace perch
