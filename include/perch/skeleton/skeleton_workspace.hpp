// SPDX-License-Identifier: BSL-1.0
/// \file
/// Workspace size for one or several skeletonisers, perch's own by default.
#pragma once

#include <cstddef>

#include "perch/skeleton/medial_axis.hpp"
#include "perch/skeleton/skeletoniser.hpp"
#include "perch/skeleton/thinning.hpp"

namespace perch {

/// Bytes of workspace the skeletonisers `S...` take at most on a `width` × `height` mask: the
/// largest of their `workspace_bytes`. Without any `S`, of perch's own (`medial_axis`,
/// `zhang_suen`, `guo_hall`), for a caller that lets its user choose among them.
template <Skeletoniser... S>
[[nodiscard]] constexpr std::size_t skeleton_workspace_bytes(int width, int height) noexcept {
  if constexpr (sizeof...(S) == 0) {
    return skeleton_workspace_bytes<medial_axis, zhang_suen, guo_hall>(width, height);
  } else {
    const std::size_t bytes[] = {S::workspace_bytes(width, height)...};
    std::size_t most = 0;
    for (const std::size_t b : bytes) most = b > most ? b : most;
    return most;
  }
}

namespace detail {

/// `S`'s bytes on a framed mask of at most `foreground` pixels (see
/// `medial_axis::framed_workspace_bytes`), or its bytes on any mask when it has no such bound.
template <Skeletoniser S>
[[nodiscard]] constexpr std::size_t framed_skeleton_bytes(int width, int height,
                                                          std::size_t foreground) noexcept {
  if constexpr (requires { S::framed_workspace_bytes(width, height, foreground); })
    return S::framed_workspace_bytes(width, height, foreground);
  else
    return S::workspace_bytes(width, height);
}

}  // namespace detail

/// Bytes of workspace the skeletonisers `S...` (perch's own without any) take at most on a
/// `width` × `height` mask of at most `foreground` pixels with a background frame, as
/// `find_perch` gives them theirs.
template <Skeletoniser... S>
[[nodiscard]] constexpr std::size_t skeleton_workspace_bytes(int width, int height,
                                                             std::size_t foreground) noexcept {
  if constexpr (sizeof...(S) == 0) {
    return skeleton_workspace_bytes<medial_axis, zhang_suen, guo_hall>(width, height, foreground);
  } else {
    const std::size_t bytes[] = {detail::framed_skeleton_bytes<S>(width, height, foreground)...};
    std::size_t most = 0;
    for (const std::size_t b : bytes) most = b > most ? b : most;
    return most;
  }
}

}  // namespace perch
