/// \file
/// Workspace size for any of perch's skeletonisers.
#pragma once

#include <cstddef>

#include "perch/skeleton/medial_axis.hpp"
#include "perch/skeleton/thinning.hpp"

namespace perch {

/// Bytes of workspace any of perch's skeletonisers (`medial_axis`, `zhang_suen`, `guo_hall`)
/// takes at most on a `width` × `height` mask: the largest of their `workspace_bytes`.
[[nodiscard]] constexpr std::size_t skeleton_workspace_bytes(int width, int height) noexcept {
  const std::size_t a = medial_axis::workspace_bytes(width, height);
  const std::size_t b = zhang_suen::workspace_bytes(width, height);
  const std::size_t c = guo_hall::workspace_bytes(width, height);
  const std::size_t ab = a > b ? a : b;
  return ab > c ? ab : c;
}

}  // namespace perch
