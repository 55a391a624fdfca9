// SPDX-License-Identifier: BSL-1.0
/// \file
/// `fill_small_holes`: fills the small holes of a binary mask (pinholes), found among the
/// background gaps between its row runs.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>

#include "perch/core/image_view.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/workspace.hpp"

namespace perch {

/// What `fill_small_holes` filled.
struct hole_fill_report {
  std::int32_t filled = 0;         ///< holes of at most the given area, now foreground
  std::int64_t filled_pixels = 0;  ///< pixels set
};

namespace detail {

/// A background gap of a row: the one before run `run` (an index in the whole run list) of
/// row `row`.
struct gap_ref {
  std::uint32_t run;
  std::int32_t row;
};


/// What a gap is to `fill_small_holes`: not yet seen, queued by the current search, leading
/// outside (or into more than the largest area), or part of a small hole.
enum class gap_state : std::uint8_t { unseen = 0, queued = 1, outside = 2, hole = 3 };

/// The breadth-first searches of `fill_small_holes` over touching gaps. Gap j is the one
/// before run j of its row (not the row's first run).
struct gap_search {
  const row_runs& runs;
  int h;
  gap_state* state;      ///< per run: its gap's state
  gap_ref* queue;        ///< the gaps the current search queued
  std::uint32_t* hint;   ///< per row: where its last look-up ended
  const row_run* base;   ///< the first run of the list
  std::size_t count = 0; ///< gaps queued by the current search

  [[nodiscard]] std::uint32_t index(const row_run& r) const noexcept {
    return static_cast<std::uint32_t>(&r - base);
  }
  [[nodiscard]] std::int64_t width(std::uint32_t j) const noexcept {
    return std::int64_t{base[j].begin} - base[j - 1].end;
  }

  /// Queues the gaps of row `y` that share a column with [b, e); false when one of them is
  /// outside or known to lead there.
  [[nodiscard]] bool touch(int y, int b, int e) noexcept {
    const bool edge_row = y == 0 || y == h - 1;  // its gaps are outside
    const std::span<const row_run> r = runs.row(y);
    // The first run that starts right of b, walked to from this row's last look-up: the gaps
    // before it, and on while they start left of e.
    std::size_t i = std::min<std::size_t>(hint[y], r.size());
    while (i > 0 && r[i - 1].begin > b) --i;
    while (i < r.size() && r[i].begin <= b) ++i;
    hint[y] = static_cast<std::uint32_t>(i);
    if (i == 0) return false;  // the gap before the row's first run
    for (; i < r.size() && r[i - 1].end < e; ++i) {
      if (edge_row) return false;
      const std::uint32_t g = index(r[i]);
      if (state[g] == gap_state::outside) return false;
      if (state[g] == gap_state::unseen) {
        state[g] = gap_state::queued;
        queue[count++] = gap_ref{g, y};
      }
    }
    return !(i == r.size() && r[i - 1].end < e);  // the gap after the row's last run
  }

  /// The search from gap `start` of row `y`: the hole's area when the gaps it reaches make a
  /// hole of at most `max_area` pixels, else -1; marks every gap it queued.
  [[nodiscard]] std::int64_t search(std::uint32_t start, int y, std::int64_t max_area) noexcept {
    count = 0;
    state[start] = gap_state::queued;
    queue[count++] = gap_ref{start, y};
    std::int64_t area = 0;
    bool small = true;
    for (std::size_t at = 0; at < count && small; ++at) {
      const gap_ref g = queue[at];
      area += width(g.run);
      const int b = base[g.run - 1].end;
      const int e = base[g.run].begin;
      small = area <= max_area && touch(g.row - 1, b, e) && touch(g.row + 1, b, e);
    }
    for (std::size_t at = 0; at < count; ++at)
      state[queue[at].run] = small ? gap_state::hole : gap_state::outside;
    return small ? area : -1;
  }
};

/// Fills the gaps marked `hole` in `mask`, and joins each row's runs across them, in place:
/// the runs move down to where the joined runs before them end (each is read before anything
/// is written there).
inline void fill_and_join(image_view<std::uint8_t> mask, row_runs& runs,
                          const gap_state* state) noexcept {
  const int h = mask.height();
  const row_run* const base = runs.row(0).data();
  std::size_t out = 0;
  for (int y = 0; y < h; ++y) {
    const std::span<const row_run> r = runs.row(y);
    std::uint8_t* row = &mask(0, y);
    const std::size_t first = out;
    int previous_end = 0;
    for (std::size_t k = 0; k < r.size(); ++k) {
      const row_run run = r[k];
      if (k > 0 && state[&r[k] - base] == gap_state::hole) {
        std::memset(row + previous_end, 1, static_cast<std::size_t>(run.begin - previous_end));
        run_list_joiner::extend_last(runs, out, run.end);
      } else {
        run_list_joiner::put(runs, out++, run);
      }
      previous_end = run.end;
    }
    run_list_joiner::set_row_start(runs, y, first);
  }
  run_list_joiner::set_row_start(runs, h, out);
}

}  // namespace detail

/// Bytes `fill_small_holes` takes from the workspace for a mask of `height` rows and `runs`
/// runs (released when the call ends).
[[nodiscard]] constexpr std::size_t fill_holes_workspace_bytes(int height,
                                                               std::size_t runs) noexcept {
  return workspace::footprint<std::uint8_t>(runs) + workspace::footprint<detail::gap_ref>(runs) +
         workspace::footprint<std::uint32_t>(height > 0 ? static_cast<std::size_t>(height) : 0);
}

/// Fills every hole of `mask` of at most `max_area` pixels and joins its runs across it.
///
/// A hole is a 4-connected component of background that does not reach the image border (the
/// dual of 8-connected foreground, as in `count_topology`). A topology-preserving skeleton
/// keeps every hole by circling it, so a pinhole in a branch (a segmenter's speckle, a
/// rasterisation pocket where two outlines meet, a leaf occluding the branch) splits the
/// branch's centreline into two paths and the branch into pieces; filling the small ones first
/// keeps the branch whole. Larger holes (the gap where limbs cross, a fork that grew together)
/// are real structure and stay. Foreground islands inside a filled hole join its rim.
/// `runs` must describe `mask` (`find_row_runs` of it, or the runs `prepare_mask` lists); on
/// return they describe the filled mask. Filled pixels are set to 1.
/// Method: the background gaps between consecutive runs of a row are the pieces of the holes,
/// and gaps of adjacent rows that share a column touch. From every gap at most `max_area`
/// wide not yet classified, a breadth-first search over touching gaps sums their widths. It
/// stops as soon as the sum exceeds `max_area`, a gap reaches the outside (before a row's first
/// run, after its last, or in the first or last row) or a gap already known to lead outside is
/// met, and then marks every gap it queued as leading outside; a search that runs out of gaps
/// has found a small hole. Each gap is queued at most once. The touching gaps of a row are
/// found by a walk from where the last look-up in that row ended (searches start in raster
/// order, so the walks are short).
/// Errors: `invalid_parameter` when `runs` do not describe `mask` or `max_area` is negative;
/// `workspace_too_small` / `out_of_memory` from the workspace (needs
/// `fill_holes_workspace_bytes(height, runs.size())`); on error the mask and runs are unchanged.
/// Complexity: O(runs + filled pixels) on masks whose holes are small next to their rows; the
/// mask is written only where holes are filled.
[[nodiscard]] inline result<hole_fill_report> fill_small_holes(image_view<std::uint8_t> mask,
                                                               row_runs& runs,
                                                               std::int64_t max_area,
                                                               workspace& ws) noexcept {
  PERCH_TRY(validate(mask));
  if (!runs.describes(mask) || max_area < 0)
    return fail(errc::invalid_parameter, "fill_small_holes: runs of another mask, or max_area < 0");
  const int h = mask.height();
  const std::size_t total = runs.size();
  hole_fill_report report;
  if (total == 0) return report;
  const auto entry = ws.mark();
  auto state = ws.allocate_zeroed<detail::gap_state>(total);
  auto queue = ws.allocate<detail::gap_ref>(total);
  auto hint = ws.allocate_zeroed<std::uint32_t>(static_cast<std::size_t>(h));
  if (auto ok = all_ok(state, queue, hint); !ok) {
    ws.rewind(entry);
    return unexpected{ok.error()};
  }
  detail::gap_search gaps{runs, h, state->data(), queue->data(), hint->data(),
                          runs.row(0).data()};
  for (int y = 1; y + 1 < h; ++y) {
    const std::span<const row_run> r = runs.row(y);
    for (std::size_t k = 1; k < r.size(); ++k) {
      const std::uint32_t start = gaps.index(r[k]);
      if (gaps.state[start] != detail::gap_state::unseen || gaps.width(start) > max_area)
        continue;
      const std::int64_t area = gaps.search(start, y, max_area);
      if (area < 0) continue;
      ++report.filled;
      report.filled_pixels += area;
    }
  }
  if (report.filled > 0) detail::fill_and_join(mask, runs, state->data());
  ws.rewind(entry);
  return report;
}

}  // namespace perch
