// SPDX-License-Identifier: BSL-1.0
/// \file
/// How much workspace `find_perch` needs: a bound from the frame's size and the caller's
/// `perch_limits` (for a fixed buffer), and the limits a call met (to state them from a corpus).
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "perch/analysis.hpp"
#include "perch/bridge.hpp"
#include "perch/core.hpp"
#include "perch/distance.hpp"
#include "perch/graph.hpp"
#include "perch/label.hpp"
#include "perch/limits.hpp"
#include "perch/pipeline.hpp"
#include "perch/policy.hpp"
#include "perch/skeleton.hpp"

namespace perch {

namespace detail {

/// Constraints a platform may have for the size query's bound to hold (the ranking keeps a
/// count and a near miss per constraint).
inline constexpr std::size_t max_sized_constraints = 64;

/// Bytes every stage from the skeleton graph on takes at most (summed: they give back only
/// their own scratch), for `pixels` skeleton pixels, a graph built with at most `nodes` nodes
/// and `branches` branches (pruning adds neither), a mask of at most `runs` runs (the search
/// for gaps to bridge), and `windows` windows on a `w` × `h` frame.
/// Limbs are at most the branches (each live branch lies on one limb) and components at most
/// the nodes (each has one). A limb's points are its branches' pixels (each skeleton pixel in
/// at most one branch) plus a node pixel per junction it runs through (a join of two branch
/// ends, fewer than its branches), so all limbs' points are at most `pixels` + `branches`,
/// which bounds the longest stretch and the obstacle discs' pixels too; at most `sites` sites
/// are ranked.
[[nodiscard]] constexpr std::size_t after_skeleton_bytes(int w, int h, std::size_t pixels,
                                                         std::size_t nodes, std::size_t branches,
                                                         std::size_t runs, std::size_t windows,
                                                         std::size_t sites) noexcept {
  const std::size_t points = pixels + branches;
  std::size_t bytes = graph_storage_bytes(pixels, nodes, branches) +
                      std::max({graph_build_scratch_bytes(pixels, nodes),
                                graph_prune_scratch_bytes(nodes, branches),
                                graph_distance_scratch_bytes(nodes),
                                gap_bridge_search_bytes(nodes, runs)});
  // The scale's sample of the skeleton and its scratch.
  bytes += workspace::footprint<pixel>(pixels) + workspace::footprint<float>(pixels);
  // Limbs: distances to the trunk, continuations, the limbs and their stretches, grounded
  // components and their areas, obstacles, neighbourhoods (two floats per point).
  bytes += workspace::footprint<float>(nodes) + workspace::footprint<std::int32_t>(2 * branches) +
           trace_limbs_workspace_bytes(branches, points) +
           workspace::footprint<branch_stretch>(branches) +
           workspace::footprint<std::uint8_t>(nodes) + workspace::footprint<float>(nodes) +
           limb_obstacles_workspace_bytes(branches, points, w, h) +
           workspace::footprint<limb_neighbourhood>(branches) +
           2 * workspace::footprint<float>(points);
  // Windows, their scratch, diameters and points on bridges; the ranking's candidates, sites (twice: ranked, then
  // in input pixels) and per-constraint counts and near misses.
  bytes += workspace::footprint<window_measures>(windows) +
           workspace::footprint<float>(window_scratch_floats(points)) +
           workspace::footprint<float>(points) + workspace::footprint<std::uint32_t>(points + 1);
  bytes += workspace::footprint<std::uint64_t>(windows) +
           2 * workspace::footprint<perch_site>(sites < windows ? sites : windows) +
           workspace::footprint<rejection_count>(max_sized_constraints) +
           2 * workspace::footprint<near_miss>(max_sized_constraints);
  return bytes;
}

/// The largest `s` with `s * s <= n`.
[[nodiscard]] constexpr std::size_t floor_sqrt(std::size_t n) noexcept {
  std::size_t lo = 0, hi = n < 2 ? n : n / 2 + 1;
  while (lo < hi) {
    const std::size_t mid = lo + (hi - lo + 1) / 2;
    if (mid <= n / mid) lo = mid; else hi = mid - 1;
  }
  return lo;
}

/// `limit` unless it is 0 (no limit) or above `most`.
[[nodiscard]] constexpr std::size_t at_most(std::size_t limit, std::size_t most) noexcept {
  return limit != 0 && limit < most ? limit : most;
}

/// The bound for an analysed frame of `w` × `h` pixels with its border (the box within it),
/// `reduction` the bytes of `prepare_mask`'s reduction and `depth` those of a depth image
/// reduced to the frame (both 0 at full size), for skeletonisers `S...`, at most `sites`
/// ranked sites and `bridges` bridges of gaps (0: bridging off).
/// Held for the whole call: the box, its runs, the depth image, the bridges (with the bridged
/// mask's runs and the bridges reported), the distance map and the skeleton; on top, one at a
/// time: the hole filling's, the distance transform's or the skeletoniser's scratch, or
/// everything from the graph on. 0 when the sum would not fit.
template <Skeletoniser... S>
[[nodiscard]] constexpr std::size_t find_perch_bytes(int w, int h, std::size_t reduction,
                                                     std::size_t depth, std::size_t sites,
                                                     std::size_t bridges,
                                                     const perch_limits& limits) noexcept {
  const auto frame = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  // Under 1 KiB per pixel, per skeleton pixel and per window: with 2 KiB of headroom for each,
  // no term or sum wraps (a 32-bit target still sizes 1920 x 1080).
  constexpr std::size_t most = std::numeric_limits<std::size_t>::max() / 2048;
  if (frame > most || limits.windows > most) return 0;
  const std::size_t box = at_most(limits.box_pixels, frame);
  const std::size_t tree = at_most(limits.tree_pixels, box);
  const std::size_t skeleton = at_most(limits.skeleton_pixels, box);
  // At most one node and one branch per skeleton pixel (`build_skeleton_graph` caps them so).
  const std::size_t nodes = at_most(limits.graph_nodes, skeleton);
  const std::size_t branches = at_most(limits.graph_branches, skeleton);
  const std::size_t runs = max_runs(box, h);
  const std::size_t held = workspace::footprint<std::uint8_t>(box) + reduction +
                           row_runs_workspace_bytes(h, runs) + depth +
                           workspace::footprint<std::uint32_t>(box) +
                           workspace::footprint<std::uint8_t>(box) +
                           workspace::footprint<gap_bridge>(bridges);
  const std::size_t bridged =
      bridges == 0 ? 0
                   : row_runs_workspace_bytes(h, runs) + workspace::footprint<perch_bridge>(bridges);
  // The box's shorter side is at most its area's square root: the skeletoniser's keys.
  const std::size_t side = std::min({floor_sqrt(box), static_cast<std::size_t>(w),
                                     static_cast<std::size_t>(h)});
  const std::size_t skeletonise = skeleton_workspace_bytes<S...>(
      static_cast<int>(side), static_cast<int>((box + side - 1) / side), tree);
  const std::size_t scratch[] = {
      fill_holes_workspace_bytes(h, runs), distance_workspace_bytes(w, h), skeletonise,
      after_skeleton_bytes(w, h, skeleton, nodes, branches, runs, limits.windows, sites)};
  std::size_t most_scratch = 0;
  for (const std::size_t s : scratch) most_scratch = s > most_scratch ? s : most_scratch;
  // An unaligned buffer loses up to one alignment to the workspace's first allocation.
  return held + bridged + most_scratch + workspace::alignment;
}

}  // namespace detail

/// Bytes of workspace `find_perch` needs at most for a `width` × `height` mask at downscale 1,
/// with skeletonisers `S...` (perch's own without any: name yours, e.g. `medial_axis`, for the
/// tightest bound) and perch's scale policies, on masks within `limits`. Give `find_perch` the
/// same limits (`perch_options::limits`) and the default `bridging`: it refuses a mask beyond
/// them with `capacity_exceeded` before taking its memory, so a borrowed buffer of this size,
/// at any alignment, never fails for lack of room. A constant expression, for a static buffer.
/// How tight: README, "Firmware and cross targets". 0 for sizes or limits `find_perch`
/// rejects before taking any workspace, and when the bound does not fit this target's `size_t`.
template <Skeletoniser... S>
[[nodiscard]] constexpr std::size_t find_perch_workspace_bytes(int width, int height,
                                                              const perch_limits& limits) noexcept {
  if (width <= 0 || height <= 0 || std::int64_t{width} * height > max_image_pixels ||
      !limits.validate())
    return 0;
  return detail::find_perch_bytes<S...>(width + 2, height + 2, 0, 0, limits.windows,
                                        bridge_options{}.max_bridges, limits);
}

/// Bytes of workspace `find_perch` needs at most for a `width` × `height` mask with `options`
/// (its downscale and `limits`; the default limits allow every pixel on the skeleton, the
/// worst case), with perch's skeletonisers and scale policies. Real trees need far less: state
/// limits or read `workspace::high_water()` after a call.
/// 0 for sizes or options `find_perch` rejects before taking any workspace (negative or zero
/// sizes, more than `max_image_pixels`, invalid options), and when the bound does not fit this
/// target's `size_t` (large frames on 32-bit targets: no buffer there could hold it).
template <Skeletoniser... S>
[[nodiscard]] inline std::size_t find_perch_workspace_bytes(int width, int height,
                                                           const perch_options& options = {}) noexcept {
  if (width <= 0 || height <= 0 || std::int64_t{width} * height > max_image_pixels ||
      !options.validate())
    return 0;
  const int w = scaled_extent(width, options.downscale);
  const int h = scaled_extent(height, options.downscale);
  const std::size_t depth =
      options.downscale < 1.0f
          ? workspace::footprint<std::uint16_t>(static_cast<std::size_t>(w) * static_cast<std::size_t>(h))
          : 0;
  return detail::find_perch_bytes<S...>(w + 2, h + 2,
                                        reduction_workspace_bytes(width, options.downscale), depth,
                                        options.ranking.top_k,
                                        options.bridging.enabled ? options.bridging.max_bridges : 0,
                                        options.limits);
}

/// The limits `result`'s mask met: `find_perch` with these (or larger) in
/// `perch_options::limits` takes the same mask, and `find_perch_workspace_bytes` for them and
/// the frame's size bounds its workspace. Take the largest of each over a corpus of your masks,
/// with margin for the masks it lacks.
[[nodiscard]] inline perch_limits measured_limits(const perch_result& result) noexcept {
  perch_limits out;
  // At least 1 each: 0 would state no limit.
  out.box_pixels = std::max<std::size_t>(result.mask.pixels.size(), 1);
  out.tree_pixels = std::max<std::size_t>(static_cast<std::size_t>(result.mask.tree_pixels), 1);
  out.skeleton_pixels = std::max<std::size_t>(result.graph.skeleton_pixels(), 1);
  out.graph_nodes =
      std::max<std::size_t>(static_cast<std::size_t>(result.graph.topology().node_id_end()), 1);
  out.graph_branches =
      std::max<std::size_t>(static_cast<std::size_t>(result.graph.topology().edge_id_end()), 1);
  out.windows = std::max<std::size_t>(result.windows_held, 1);
  return out;
}

}  // namespace perch
