// SPDX-License-Identifier: BSL-1.0
/// \file
/// The camera's attitude in the image: where the true horizontal is, so slopes are measured
/// against gravity and not against the image rows (the paper's future work on attitude sensors).
#pragma once

#include <cmath>
#include <numbers>

#include "perch/core/geometry.hpp"
#include "perch/core/result.hpp"

namespace perch {

/// The true horizontal in the image, as a unit direction (x right, y down).
///
/// `roll_deg` is the angle from the image x axis to the true horizon, positive toward +y
/// (clockwise on screen): a camera rolled so that the horizon runs down to the right by 10°
/// has `roll_deg = 10`. Equivalently give the gravity direction in the image with
/// `from_gravity` (default gravity (0, 1): straight down the image).
struct attitude {
  float roll_deg = 0.0f;

  /// The attitude whose gravity points along `gravity_px` (any non-zero length).
  [[nodiscard]] static attitude from_gravity(point2f gravity_px) noexcept {
    // Horizon is gravity rotated by -90°: (gx, gy) -> (gy, -gx).
    const float angle = std::atan2(-gravity_px.x(), gravity_px.y());
    return {angle * 180.0f / std::numbers::pi_v<float>};
  }

  /// Unit vector along the true horizontal.
  [[nodiscard]] point2f horizon() const noexcept {
    const float a = roll_deg * std::numbers::pi_v<float> / 180.0f;
    return {std::cos(a), std::sin(a)};
  }
  /// Unit vector pointing up (against gravity).
  [[nodiscard]] point2f up() const noexcept {
    const point2f h = horizon();
    return {h.y(), -h.x()};
  }

  [[nodiscard]] status validate() const noexcept {
    if (!std::isfinite(roll_deg)) return fail(errc::invalid_parameter, "attitude.roll_deg");
    return {};
  }
};

/// Angle in degrees between direction `d` and the horizon `h` (unit), folded into [0°, 90°]:
/// a branch's slope does not depend on which way it is walked.
[[nodiscard]] inline float slope_to_horizon_deg(point2f d, point2f h) noexcept {
  const float cross = h.x() * d.y() - h.y() * d.x();
  const float dot = h.x() * d.x() + h.y() * d.y();
  if (cross == 0.0f && dot == 0.0f) return 0.0f;
  float a = std::abs(std::atan2(cross, dot)) * 180.0f / std::numbers::pi_v<float>;
  if (a > 90.0f) a = 180.0f - a;
  return a;
}

/// Direction `d` (image coordinates, y down) in degrees from the image's +x axis,
/// counter-clockwise as seen with y up, in (−180°, 180°]; 0 for a zero vector.
[[nodiscard]] inline float heading_deg(point2f d) noexcept {
  if (d.x() == 0.0f && d.y() == 0.0f) return 0.0f;
  const float a = std::atan2(-d.y(), d.x()) * 180.0f / std::numbers::pi_v<float>;
  return a == -180.0f ? 180.0f : a;
}

}  // namespace perch
