// SPDX-License-Identifier: BSL-1.0
/// \file
/// Points at the boundary of the library, as Eigen types, and the integer pixel inside it.
#pragma once

#include <Eigen/Core>
#include <cmath>
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

/// The unit principal axis of a scatter of points with centred second moments `sxx`, `sxy`,
/// `syy` (orthogonal least squares): the eigenvector of the larger eigenvalue of the symmetric
/// 2 × 2 matrix [[sxx, sxy], [sxy, syy]], in closed form (no trigonometry: the same on every
/// target). Unsigned (either direction along the axis); zero for an isotropic scatter, which
/// has no axis.
[[nodiscard]] inline point2f principal_axis(double sxx, double sxy, double syy) noexcept {
  const double half_diff = 0.5 * (sxx - syy);
  const double root = std::sqrt(half_diff * half_diff + sxy * sxy);
  if (!(root > 0)) return point2f::Zero();
  // (half_diff + root, sxy) and (sxy, root − half_diff) both span the axis; each is the
  // well-conditioned one on its side of half_diff = 0.
  const double vx = half_diff >= 0 ? half_diff + root : sxy;
  const double vy = half_diff >= 0 ? sxy : root - half_diff;
  const double norm = std::sqrt(vx * vx + vy * vy);
  return {static_cast<float>(vx / norm), static_cast<float>(vy / norm)};
}

/// The 8 neighbour offsets in a fixed order: E, NE, N, NW, W, SW, S, SE (counter-clockwise on
/// screen, starting east). Used wherever a neighbourhood is walked, so ties break the same way.
inline constexpr pixel neighbours8[8] = {{1, 0},  {1, -1}, {0, -1}, {-1, -1},
                                         {-1, 0}, {-1, 1}, {0, 1},  {1, 1}};

}  // namespace perch
