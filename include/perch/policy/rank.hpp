// SPDX-License-Identifier: BSL-1.0
/// \file
/// Viability and ranking (paper §"Rank viable branches"): every window is checked against a
/// platform's constraints, the viable ones are scored, and the best distinct sites are ranked.
/// Diagnostics say why every other window lost: rejections per constraint, and for each
/// constraint the closest window that failed only on it, with by how much.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string_view>

#include "perch/analysis/clearance.hpp"
#include "perch/analysis/measures.hpp"
#include "perch/core/bounded_vector.hpp"
#include "perch/core/result.hpp"
#include "perch/core/workspace.hpp"
#include "perch/policy/composites.hpp"
#include "perch/policy/concepts.hpp"

namespace perch {

/// A ranked perch site: the winning window's measures and its penalty (paper eq. 3 by default).
struct perch_site {
  window_measures window{};  ///< `window.centre` is the perch pixel on the centreline
  float penalty = 0;         ///< lower is better
  std::uint32_t rank = 0;    ///< 0 for the best site
};

/// How many windows a constraint rejected (counted on the first constraint a window fails, in
/// the platform's declared order).
struct rejection_count {
  std::string_view constraint{};
  std::string_view unit{};
  std::uint32_t windows = 0;
};

/// The closest window that failed only `constraint`, and by how much (in `unit`).
struct near_miss {
  std::string_view constraint{};
  std::string_view unit{};
  float miss = 0;
  window_measures window{};
  bool present = false;  ///< false when no window failed on this constraint alone
};

/// Ranking options.
struct rank_options {
  std::size_t top_k = 5;             ///< sites to return
  float site_separation_mm = 90.0f;  ///< ranked sites are at least this far apart
};

/// Everything `rank_windows` produces. Spans point into the workspace.
struct ranking {
  std::span<const perch_site> sites{};
  std::span<const rejection_count> rejections{};
  std::span<const near_miss> near_misses{};
  std::uint32_t windows = 0;  ///< windows examined
  std::uint32_t viable = 0;   ///< windows that passed every constraint
};

namespace detail {

/// A viable window: its penalty and its index among the windows.
struct ranking_candidate {
  float penalty;
  std::uint32_t index;
};

/// Checks every window against every leaf of `constraints` (the geometric ones first; the
/// clearance ones only when those all pass, with the context `make_context(m)` built once, on
/// the first clearance query): a viable window is scored into `candidates`, any other counted
/// against the first constraint it fails, and kept in `misses` when it failed only that one
/// and by less than the window kept there. With a `scale_uncertainty` u > 0 each constraint
/// reads the window at both ends of its scale's range (`at_scale`, 1 − u and 1 + u) and misses
/// by the larger. Returns the number of viable windows. (One loop: the checks stay inlined in
/// it.)
template <Constraint C, Scorer S, class MakeContext>
[[nodiscard]] std::size_t judge_windows(std::span<const window_measures> windows,
                                        const C& constraints, const S& scorer,
                                        MakeContext& make_context, float scale_uncertainty,
                                        std::span<ranking_candidate> candidates,
                                        std::span<rejection_count> rejections,
                                        std::span<near_miss> misses) noexcept {
  std::size_t viable = 0;
  const bool uncertain = scale_uncertainty > 0;
  for (std::size_t w = 0; w < windows.size(); ++w) {
    const window_measures& m = windows[w];
    const window_measures fine = uncertain ? at_scale(m, 1.0f - scale_uncertainty) : m;
    const window_measures coarse = uncertain ? at_scale(m, 1.0f + scale_uncertainty) : m;
    std::size_t failed = 0;
    std::size_t first_failed = leaf_count<C>;
    float first_miss = 0;
    auto note = [&](std::size_t leaf, float miss) {
      if (!(miss <= 0)) {  // NaN counts as a failure
        if (failed++ == 0) {
          first_failed = leaf;
          first_miss = miss;
        }
      }
    };
    for_each_leaf(constraints, [&](const auto& leaf, std::size_t i) {
      if constexpr (GeometricConstraint<std::remove_cvref_t<decltype(leaf)>>)
        note(i, uncertain ? std::max(leaf(fine), leaf(coarse)) : leaf(m));
    });
    if (failed == 0) {
      std::optional<window_context> context, fine_context, coarse_context;
      for_each_leaf(constraints, [&](const auto& leaf, std::size_t i) {
        using leaf_type = std::remove_cvref_t<decltype(leaf)>;
        if constexpr (!GeometricConstraint<leaf_type> && ContextConstraint<leaf_type>) {
          if (!uncertain) {
            if (!context) context.emplace(make_context(m));
            note(i, leaf(m, *context));
          } else {
            if (!fine_context) fine_context.emplace(make_context(fine));
            if (!coarse_context) coarse_context.emplace(make_context(coarse));
            note(i, std::max(leaf(fine, *fine_context), leaf(coarse, *coarse_context)));
          }
        }
      });
    }
    if (failed == 0) {
      candidates[viable++] = {static_cast<float>(scorer(m)), static_cast<std::uint32_t>(w)};
      continue;
    }
    ++rejections[first_failed].windows;
    near_miss& best = misses[first_failed];
    if (failed == 1 && (!best.present || first_miss < best.miss)) {
      best.miss = first_miss;
      best.window = m;
      best.present = true;
    }
  }
  return viable;
}

/// The best of `candidates` (sorted) whose centres are at least `separation_mm` apart, into
/// `sites` (as many as fit); returns how many.
inline std::size_t choose_distinct_sites(std::span<const window_measures> windows,
                                         std::span<const ranking_candidate> candidates,
                                         float separation_mm, std::span<perch_site> sites) noexcept {
  std::size_t chosen = 0;
  for (std::size_t c = 0; c < candidates.size() && chosen < sites.size(); ++c) {
    const window_measures& m = windows[candidates[c].index];
    bool distinct = true;
    for (std::size_t s = 0; s < chosen && distinct; ++s) {
      const window_measures& o = sites[s].window;
      const float dx = static_cast<float>(m.centre.x - o.centre.x);
      const float dy = static_cast<float>(m.centre.y - o.centre.y);
      const float mm = std::sqrt(dx * dx + dy * dy) * 0.5f * (m.mm_per_px + o.mm_per_px);
      distinct = mm >= separation_mm;
    }
    if (!distinct) continue;
    sites[chosen] = {m, candidates[c].penalty, static_cast<std::uint32_t>(chosen)};
    ++chosen;
  }
  return chosen;
}

}  // namespace detail

/// Checks every window of `windows` against `constraints`, scores the viable ones with `scorer`,
/// and returns the `top_k` lowest penalties whose centres are at least `site_separation_mm`
/// apart. Ties break by branch, then window start: deterministic.
/// `make_context(window)` builds the `window_context` for clearance constraints; it is called
/// only for windows that passed every geometric constraint. `scale_uncertainty`: the windows'
/// scale's (`perch::scale_uncertainty`); every constraint then holds at both ends of it.
/// Complexity: O(windows · constraints + viable · log viable) plus the clearance queries.
template <Constraint C, Scorer S, class MakeContext>
[[nodiscard]] result<ranking> rank_windows(std::span<const window_measures> windows,
                                           const C& constraints, const S& scorer,
                                           MakeContext&& make_context, workspace& ws,
                                           const rank_options& options = {},
                                           float scale_uncertainty = 0.0f) noexcept {
  constexpr std::size_t leaves = leaf_count<C>;
  auto rejections = ws.allocate<rejection_count>(leaves);
  auto misses = ws.allocate<near_miss>(leaves);
  PERCH_TRY(all_ok(rejections, misses));
  for_each_leaf(constraints, [&](const auto& leaf, std::size_t i) {
    using leaf_type = std::remove_cvref_t<decltype(leaf)>;
    (*rejections)[i] = {leaf_type::name, leaf_type::unit, 0};
    (*misses)[i] = {leaf_type::name, leaf_type::unit, 0, {}, false};
  });
  auto candidates = ws.allocate<detail::ranking_candidate>(windows.size());
  PERCH_TRY(all_ok(candidates));
  const std::size_t viable = detail::judge_windows(windows, constraints, scorer, make_context,
                                                  scale_uncertainty, *candidates, *rejections,
                                                  *misses);

  std::sort(candidates->begin(), candidates->begin() + static_cast<std::ptrdiff_t>(viable),
            [&windows](const detail::ranking_candidate& a, const detail::ranking_candidate& b) {
              if (a.penalty != b.penalty) return a.penalty < b.penalty;
              const window_measures& wa = windows[a.index];
              const window_measures& wb = windows[b.index];
              if (wa.limb != wb.limb) return wa.limb < wb.limb;
              return wa.first < wb.first;
            });
  auto sites = ws.allocate<perch_site>(std::min(options.top_k, viable));
  PERCH_TRY(all_ok(sites));
  const std::size_t chosen = detail::choose_distinct_sites(
      windows, candidates->first(viable), options.site_separation_mm, *sites);
  ranking out;
  out.sites = sites->first(chosen);
  out.rejections = *rejections;
  out.near_misses = *misses;
  out.windows = static_cast<std::uint32_t>(windows.size());
  out.viable = static_cast<std::uint32_t>(viable);
  return out;
}

}  // namespace perch
