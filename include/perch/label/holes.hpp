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
  auto state_memory = ws.allocate_zeroed<std::uint8_t>(total);
  auto queue_memory = ws.allocate<detail::gap_ref>(total);
  auto hint_memory = ws.allocate_zeroed<std::uint32_t>(static_cast<std::size_t>(h));
  if (!state_memory || !queue_memory || !hint_memory) {
    ws.rewind(entry);
    return unexpected{!state_memory   ? state_memory.error()
                      : !queue_memory ? queue_memory.error()
                                      : hint_memory.error()};
  }
  // Gap j (before run j of its row, not the row's first run): not yet seen, queued by the
  // current search, leading outside (or into more than max_area), or part of a small hole.
  enum : std::uint8_t { unseen = 0, queued = 1, outside = 2, hole = 3 };
  std::uint8_t* state = state_memory->data();
  detail::gap_ref* queue = queue_memory->data();
  std::uint32_t* hint = hint_memory->data();
  const row_run* const base = runs.row(0).data();
  auto index = [base](const row_run& r) { return static_cast<std::uint32_t>(&r - base); };
  auto width = [base](std::uint32_t j) { return std::int64_t{base[j].begin} - base[j - 1].end; };

  // Queues the gaps of row `y` that share a column with [b, e); false when one of them is
  // outside or known to lead there.
  std::size_t count = 0;
  auto touch = [&](int y, int b, int e) {
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
      if (state[g] == outside) return false;
      if (state[g] == unseen) {
        state[g] = queued;
        queue[count++] = detail::gap_ref{g, y};
      }
    }
    return !(i == r.size() && r[i - 1].end < e);  // the gap after the row's last run
  };

  for (int y = 1; y + 1 < h; ++y) {
    const std::span<const row_run> r = runs.row(y);
    for (std::size_t k = 1; k < r.size(); ++k) {
      const std::uint32_t start = index(r[k]);
      if (state[start] != unseen || width(start) > max_area) continue;
      count = 0;
      state[start] = queued;
      queue[count++] = detail::gap_ref{start, y};
      std::int64_t area = 0;
      bool small = true;
      for (std::size_t at = 0; at < count && small; ++at) {
        const detail::gap_ref g = queue[at];
        area += width(g.run);
        const int b = base[g.run - 1].end;
        const int e = base[g.run].begin;
        small = area <= max_area && touch(g.row - 1, b, e) && touch(g.row + 1, b, e);
      }
      for (std::size_t at = 0; at < count; ++at) state[queue[at].run] = small ? hole : outside;
      if (!small) continue;
      ++report.filled;
      report.filled_pixels += area;
    }
  }
  if (report.filled > 0) {
    // Fill, and join each row's runs across the filled gaps, in place: the runs move down to
    // where the joined runs before them end (each is read before anything is written there).
    std::size_t out = 0;
    for (int y = 0; y < h; ++y) {
      const std::span<const row_run> r = runs.row(y);
      std::uint8_t* row = &mask(0, y);
      const std::size_t first = out;
      int previous_end = 0;
      for (std::size_t k = 0; k < r.size(); ++k) {
        const row_run run = r[k];
        if (k > 0 && state[index(r[k])] == hole) {
          std::memset(row + previous_end, 1, static_cast<std::size_t>(run.begin - previous_end));
          detail::run_list_joiner::extend_last(runs, out, run.end);
        } else {
          detail::run_list_joiner::put(runs, out++, run);
        }
        previous_end = run.end;
      }
      detail::run_list_joiner::set_row_start(runs, y, first);
    }
    detail::run_list_joiner::set_row_start(runs, h, out);
  }
  ws.rewind(entry);
  return report;
}

}  // namespace perch
