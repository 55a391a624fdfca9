// SPDX-License-Identifier: BSL-1.0
/// \file
/// The `Skeletoniser` concept every skeleton method models, so the pipeline takes any of them;
/// `RowRunSkeletoniser`, for a method that can read its mask's foreground from the row runs;
/// and the option every method shares: how thin the output must be.
#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "perch/core/image_view.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/workspace.hpp"

namespace perch {

/// How thin a skeleton must be.
enum class thinness : std::uint8_t {
  /// One pixel thin: after the method, a topology-preserving clean-up removes every 2×2 block
  /// of skeleton pixels (deleting simple pixels, or re-routing a branch through mask pixels
  /// next to the block where no block pixel is simple); components and holes stay as the
  /// method left them. Topology comes first: a block stays only where the mask is hardly
  /// wider than the skeleton around it and leaves no short re-route (noise masks), and some
  /// masks have no thin subset with their topology at all (see `detail::remove_blocks`).
  one_pixel,
  /// Exactly the method's own output as its paper defines it (Zhang–Suen and Guo–Hall leave
  /// 2×2 blocks on most tree masks): for comparing with the papers and other libraries.
  faithful,
};

/// A skeletonisation method: called as
/// `s(mask, dist2, skeleton, ws)` → `status`, noexcept, where `mask` is the tree (non-zero =
/// tree), `dist2` its squared distance map (from `distance_transform_sq`), and `skeleton` the
/// output (written everywhere: 1 skeleton, 0 not); `S::name` names the method in diagnostics;
/// `S::workspace_bytes(width, height)` is the workspace the call takes at most (given back on
/// return).
template <class S>
concept Skeletoniser = requires(const S& s, image_view<const std::uint8_t> mask,
                                image_view<const std::uint32_t> dist2,
                                image_view<std::uint8_t> skeleton, workspace& ws, int extent) {
  { s(mask, dist2, skeleton, ws) } noexcept -> std::same_as<status>;
  { S::name } -> std::convertible_to<std::string_view>;
  { S::workspace_bytes(extent, extent) } noexcept -> std::same_as<std::size_t>;
};

/// A `Skeletoniser` that can also take the row runs of its mask (`row_runs`), to read the
/// foreground from them instead of scanning the whole image for it: called as
/// `s(mask, dist2, skeleton, ws, runs)` → `status`, noexcept, with the same skeleton as
/// without them. Runs that do not `describe` `mask` are ignored (the method scans); runs that
/// do must list all of its foreground, i.e. be found on it (`find_row_runs`, `prepare_mask`)
/// and the mask unchanged since. Its skeleton lies inside the mask, hence inside the runs, so
/// the graph may look for skeleton pixels only there (`build_skeleton_graph`'s `within`).
/// `find_perch` hands the runs it found to every skeletoniser that models this, and to the
/// graph after it; any other skeletoniser, and the graph after it, scan. perch's own
/// (`medial_axis`, `zhang_suen`, `guo_hall`) model it.
template <class S>
concept RowRunSkeletoniser =
    Skeletoniser<S> && requires(const S& s, image_view<const std::uint8_t> mask,
                                image_view<const std::uint32_t> dist2,
                                image_view<std::uint8_t> skeleton, workspace& ws,
                                const row_runs& runs) {
      { s(mask, dist2, skeleton, ws, runs) } noexcept -> std::same_as<status>;
    };

}  // namespace perch
