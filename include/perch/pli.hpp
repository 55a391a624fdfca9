// SPDX-License-Identifier: BSL-1.0
/// \file
/// perch: where a tree-perching drone should grasp a tree (the PLI method of "Perch Location
/// Identification", with the reference prototype's defects fixed and the paper's future work
/// done). The one include a user needs: every stage, in data-flow order, and `find_perch`.
///
///   mask → distance transform → skeleton → skeleton graph → weighting + pruning
///        → windows + measures → constraints → scorer → ranked perch sites + diagnostics
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <string_view>
#include <utility>

#include "perch/analysis.hpp"
#include "perch/core.hpp"
#include "perch/distance.hpp"
#include "perch/graph.hpp"
#include "perch/label.hpp"
#include "perch/pipeline.hpp"
#include "perch/platform.hpp"
#include "perch/policy.hpp"
#include "perch/skeleton.hpp"

namespace perch {


/// Bytes of workspace `find_perch` needs at most for a `width` × `height` mask (every pixel
/// tree, the worst case); give a borrowed workspace this much and it never fails for lack of
/// room. Real trees need far less: `workspace::high_water()` after a call says how much.
/// 0 for sizes or options `find_perch` rejects before taking any workspace (negative or zero
/// sizes, more than `max_image_pixels`, invalid options), and when the bound does not fit this
/// target's `size_t` (large frames on 32-bit targets: no buffer there could hold it).
[[nodiscard]] inline std::size_t find_perch_workspace_bytes(int width, int height,
                                                           const perch_options& options = {}) noexcept {
  if (width <= 0 || height <= 0 || std::int64_t{width} * height > max_image_pixels ||
      !options.validate())
    return 0;
  const int w = scaled_extent(width, options.downscale) + 2;
  const int h = scaled_extent(height, options.downscale) + 2;
  const auto n = static_cast<std::size_t>(w) * static_cast<std::size_t>(h);
  // The bound is under 1 KiB per pixel plus per window: with 2 KiB of headroom for each, no
  // term or sum wraps (a 32-bit target still sizes 1920 x 1080).
  constexpr std::size_t most = std::numeric_limits<std::size_t>::max() / 2048;
  if (n > most || options.max_windows > most) return 0;
  std::size_t bytes = prepare_mask_workspace_bytes(width, height, options.downscale);
  bytes += row_runs_workspace_bytes(h, detail::max_runs(w, h)) +
           fill_holes_workspace_bytes(h, detail::max_runs(w, h));
  bytes += workspace::footprint<std::uint32_t>(n) + workspace::footprint<std::uint8_t>(n);
  bytes += distance_workspace_bytes(w, h);
  bytes += skeleton_workspace_bytes(w, h);
  bytes += skeleton_graph_workspace_bytes(w, h, n);
  // Limbs: continuations, the limbs (at most one per edge, at most one edge per skeleton
  // pixel) and their stretches.
  bytes += workspace::footprint<std::int32_t>(2 * n) + trace_limbs_workspace_bytes(n, n) +
           workspace::footprint<branch_stretch>(n);
  // What surrounds the limbs: grounded components, obstacle discs, the clearance cache.
  bytes += workspace::footprint<std::uint8_t>(n) + workspace::footprint<float>(n) +
           limb_obstacles_workspace_bytes(n, n, w, h) +
           workspace::footprint<limb_neighbourhood>(n) + 2 * workspace::footprint<float>(n);
  bytes += workspace::footprint<window_measures>(options.max_windows);
  bytes += workspace::footprint<float>(window_scratch_floats(n));
  bytes += 2 * workspace::footprint<float>(n) + (std::size_t{64} << 10);
  return bytes;
}

/// Finds where `platform` can perch on the tree of `mask` (non-zero = tree).
///
/// Runs the whole PLI pipeline on the tree's bounding box: distance transform, skeleton
/// (`skeletoniser`, medial axis by default), skeleton graph of every connected component,
/// weighting and pruning (paper eq. 1), windows one drone width long along every branch,
/// measures, the platform's constraints and scorer (paper eq. 3), and ranks the best
/// `options.ranking.top_k` sites at least `site_separation_mm` apart.
/// "No perch" and "no tree" are outcomes, not errors: the result then says why (rejections per
/// constraint and the near misses).
/// Errors: view errors of `mask` (null data, stride, size), invalid options, platform or scale
/// (with the parameter named), `capacity_exceeded` when the tree has more windows than
/// `options.max_windows`, `workspace_too_small` for a borrowed workspace (see
/// `find_perch_workspace_bytes`), and a scale policy's own errors (e.g. `no_valid_depth`).
/// Allocation: none once the workspace has grown to this mask's needs (a second call on a
/// similar mask allocates nothing). Resets `ws`: results of a previous call on it are gone.
/// Deterministic: the same input gives bit-identical output.
/// Complexity: linear in the tree's bounding-box pixels plus windows × window length.
template <BinaryView Mask, Platform P, ScalePolicy Scale, Skeletoniser Skel>
[[nodiscard]] result<perch_result> find_perch(const Mask& mask, const P& platform,
                                              const Scale& scale, const Skel& skeletoniser,
                                              workspace& ws,
                                              const perch_options& options = {}) noexcept {
  ws.reset();
  detail::stage_clock clock(options.clock);
  const std::size_t blocks_before = ws.upstream_allocations();
  PERCH_TRY(validate_non_empty(mask));
  PERCH_TRY(options.validate());
  PERCH_TRY(validate_platform(platform));
  perch_result out;
  out.width = mask.width();
  out.height = mask.height();
  out.scale = Scale::name;
  out.platform = P::name;
  detail::pipeline_state<Scale> state;

  PERCH_TRY(detail::prepare_stage(mask, scale, options, ws, out, state));
  out.timing.prepare_ms = clock.lap();
  // The totals of a call, whichever stage it ends after.
  auto finished = [&]() -> result<perch_result> {
    out.timing.total_ms = clock.total();
    out.cold = ws.upstream_allocations() != blocks_before;
    return std::move(out);
  };
  if (out.mask.tree_pixels == 0) return finished();
  PERCH_TRY(detail::distance_stage(ws, out, state));
  out.timing.distance_ms = clock.lap();
  PERCH_TRY(detail::skeleton_stage(skeletoniser, ws, out, state));
  out.timing.skeleton_ms = clock.lap();
  PERCH_TRY(detail::graph_stage(ws, out, state));
  out.timing.graph_ms = clock.lap();
  PERCH_TRY(detail::scale_and_prune_stage(platform, options, ws, out, state));
  out.timing.prune_ms = clock.lap();
  PERCH_TRY(detail::limb_stage(options, ws, out, state));
  PERCH_TRY(detail::window_stage(mask, platform, options, ws, out, state));
  out.timing.windows_ms = clock.lap();
  PERCH_TRY(detail::ranking_stage(platform, options, ws, out, state));
  out.timing.ranking_ms = clock.lap();
  return finished();
}

/// `find_perch` with the default skeleton (medial axis).
template <BinaryView Mask, Platform P, ScalePolicy Scale>
[[nodiscard]] result<perch_result> find_perch(const Mask& mask, const P& platform,
                                              const Scale& scale, workspace& ws,
                                              const perch_options& options = {}) noexcept {
  return find_perch(mask, platform, scale, medial_axis{}, ws, options);
}

/// `find_perch` for the paper's platform (tendon-driven claw) and scale (the trunk prior).
template <BinaryView Mask>
[[nodiscard]] result<perch_result> find_perch(const Mask& mask, workspace& ws,
                                              const perch_options& options = {}) noexcept {
  return find_perch(mask, tendon_claw{}, trunk_prior{}, medial_axis{}, ws, options);
}

}  // namespace perch
