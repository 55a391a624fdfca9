// SPDX-License-Identifier: BSL-1.0
/// \file
/// Points at the boundary of the library, as Eigen types, and the integer pixel inside it.
#pragma once

#include <Eigen/Core>
#include <cstdint>

namespace perch {

/// A point in image coordinates (x = column, y = row, origin top-left, y down), in pixels.
using point2f = Eigen::Vector2f;
/// A point in the camera frame (x right, y down, z forward), in metres.
using point3f = Eigen::Vector3f;

/// An integer pixel position (x = column, y = row).
struct pixel {
  std::int32_t x = 0;
  std::int32_t y = 0;
  friend constexpr bool operator==(pixel, pixel) noexcept = default;
};

/// The centre of pixel `p` as a `point2f`.
[[nodiscard]] inline point2f to_point(pixel p) noexcept {
  return {static_cast<float>(p.x), static_cast<float>(p.y)};
}

/// The 8 neighbour offsets in a fixed order: E, NE, N, NW, W, SW, S, SE (counter-clockwise on
/// screen, starting east). Used wherever a neighbourhood is walked, so ties break the same way.
inline constexpr pixel neighbours8[8] = {{1, 0},  {1, -1}, {0, -1}, {-1, -1},
                                         {-1, 0}, {-1, 1}, {0, 1},  {1, 1}};

}  // namespace perch
