// SPDX-License-Identifier: BSL-1.0
/// \file
/// perch: where a tree-perching drone should grasp a tree (the PLI method of "Perch Location
/// Identification", with the reference prototype's defects fixed and the paper's future work
/// done). The one include a user needs: every stage, in data-flow order, and `find_perch`.
///
///   mask → distance transform → skeleton → skeleton graph → weighting + pruning
///        → gaps bridged (and the mask's stages again) → windows + measures → constraints
///        → scorer → ranked perch sites + diagnostics
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
#include "perch/bridge.hpp"
#include "perch/core.hpp"
#include "perch/distance.hpp"
#include "perch/graph.hpp"
#include "perch/label.hpp"
#include "perch/pipeline.hpp"
#include "perch/platform.hpp"
#include "perch/policy.hpp"
#include "perch/size_query.hpp"
#include "perch/skeleton.hpp"

namespace perch {

/// Finds where `platform` can perch on the tree of `mask` (non-zero = tree).
///
/// Runs the whole PLI pipeline on the tree's bounding box: distance transform, skeleton
/// (`skeletoniser`, medial axis by default), skeleton graph of every connected component,
/// weighting and pruning (paper eq. 1), small segmentation gaps bridged (`options.bridging`:
/// the stages so far then run again on the bridged mask), windows one drone width long along
/// every branch,
/// measures, the platform's constraints and scorer (paper eq. 3), and ranks the best
/// `options.ranking.top_k` sites at least `site_separation_mm` apart.
/// "No perch" and "no tree" are outcomes, not errors: the result then says why (rejections per
/// constraint and the near misses).
/// Errors: view errors of `mask` (null data, stride, size), invalid options, platform or scale
/// (with the parameter named), `capacity_exceeded` when the mask needs more than
/// `options.limits` (the limit named), `workspace_too_small` for a borrowed workspace (see
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
  out.scale_uncertainty = scale_uncertainty(scale);
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
  // The mask's stages, from its distances to its pruned skeleton graph.
  auto analyse_mask = [&]() -> status {
    PERCH_TRY(detail::distance_stage(ws, out, state));
    out.timing.distance_ms += clock.lap();
    PERCH_TRY(detail::skeleton_stage(skeletoniser, ws, out, state));
    out.timing.skeleton_ms += clock.lap();
    PERCH_TRY(detail::graph_stage(options, ws, out, state));
    out.timing.graph_ms += clock.lap();
    PERCH_TRY(detail::scale_and_prune_stage(platform, options, ws, out, state));
    out.timing.prune_ms += clock.lap();
    return {};
  };
  const workspace::checkpoint unbridged = ws.mark();
  PERCH_TRY(analyse_mask());
  auto bridged = detail::bridge_stage(options, unbridged, ws, out, state);
  PERCH_TRY(all_ok(bridged));
  out.timing.bridge_ms = clock.lap();
  if (*bridged) PERCH_TRY(analyse_mask());
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
