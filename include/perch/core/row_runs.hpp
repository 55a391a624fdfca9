// SPDX-License-Identifier: BSL-1.0
/// \file
/// `row_runs`: the runs of foreground of a binary image, row by row, found once and shared by the
/// kernels that would otherwise each scan the whole image for them (the distance transform's two
/// passes, the skeletonisers' first pass). On a thin tree most of a frame is background between
/// a few runs per row, so a list of runs replaces several whole-image scans by one.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "perch/core/image_view.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_scan.hpp"
#include "perch/core/workspace.hpp"

namespace perch {

/// The foreground pixels [begin, end) of one row. (No default member values: the workspace
/// would then zero every slot of a run list on each call.)
struct row_run {
  std::int32_t begin;
  std::int32_t end;
};

namespace detail {
class run_list_builder;
class run_list_joiner;
}  // namespace detail

/// The foreground runs of every row of one binary image, in raster order.
///
/// Made by `find_row_runs`, which records the image it describes (data pointer, size, stride).
/// Kernels that take one use it only when it `describes` the image they are given; for any other
/// image (or a default-constructed `row_runs`) they scan the image themselves, with the same
/// result. It borrows workspace memory: valid until that memory is rewound, and only while the
/// image's foreground is unchanged.
class row_runs {
 public:
  constexpr row_runs() noexcept = default;

  /// Whether these are the runs of `view` (same pixels in memory, same size and stride).
  template <ImageView V>
  [[nodiscard]] bool describes(const V& view) const noexcept {
    return first_ != nullptr && static_cast<const void*>(view.data()) == data_ &&
           view.width() == width_ && view.height() == height_ && view.stride() == stride_;
  }
  /// Whether these are runs of an image of `view`'s size (so their rows and columns index
  /// `view`'s).
  template <ImageView V>
  [[nodiscard]] bool spans(const V& view) const noexcept {
    return first_ != nullptr && view.width() == width_ && view.height() == height_;
  }
  /// The runs of row `y`, left to right. Precondition: 0 ≤ y < height of the image.
  [[nodiscard]] std::span<const row_run> row(int y) const noexcept {
    PERCH_ASSERT(first_ != nullptr && y >= 0 && y < height_, "row_runs::row: no such row");
    const auto at = static_cast<std::size_t>(y);
    return {runs_ + first_[at], runs_ + first_[at + 1]};
  }
  /// The number of runs in the image.
  [[nodiscard]] std::size_t size() const noexcept {
    return first_ == nullptr ? 0 : first_[static_cast<std::size_t>(height_)];
  }

 private:
  friend class detail::run_list_builder;
  friend class detail::run_list_joiner;

  const void* data_ = nullptr;
  int width_ = 0;
  int height_ = 0;
  std::ptrdiff_t stride_ = 0;
  std::uint32_t* first_ = nullptr;  ///< height + 1 entries: row y is runs [first[y], first[y+1])
  row_run* runs_ = nullptr;
};

/// Bytes of workspace `find_row_runs` takes for a mask of `height` rows and `max_runs` runs.
[[nodiscard]] constexpr std::size_t row_runs_workspace_bytes(int height,
                                                             std::size_t max_runs) noexcept {
  if (height <= 0) return 0;
  return workspace::footprint<std::uint32_t>(static_cast<std::size_t>(height) + 1) +
         workspace::footprint<row_run>(max_runs);
}

namespace detail {

/// Lists the runs of an image row by row, from top to bottom, into workspace memory: what
/// `find_row_runs` does with a scan of the image, and `prepare_mask` while it copies the mask.
class run_list_builder {
 public:
  /// Room for `max_runs` runs of an image of `height` rows.
  [[nodiscard]] static result<run_list_builder> make(workspace& ws, int height,
                                                     std::size_t max_runs) noexcept {
    const auto entry = ws.mark();
    auto first = ws.allocate<std::uint32_t>(static_cast<std::size_t>(height) + 1);
    PERCH_TRY(all_ok(first));
    auto runs = ws.allocate<row_run>(max_runs);
    if (auto ok = all_ok(runs); !ok) {
      ws.rewind(entry);
      return unexpected{ok.error()};
    }
    run_list_builder b;
    b.first_ = first->data();
    b.runs_ = runs->data();
    b.max_ = max_runs;
    return b;
  }
  /// Starts row `y` (rows in order 0, 1, …).
  void start_row(int y) noexcept {
    first_[static_cast<std::size_t>(y)] = static_cast<std::uint32_t>(count_);
  }
  /// Adds the run [begin, end) to the current row; false (nothing added) when the list is full.
  [[nodiscard]] bool add(int begin, int end) noexcept {
    if (count_ == max_) return false;
    runs_[count_++] = row_run{begin, end};
    return true;
  }
  /// The runs of the image at `data` (`width` × `height`, `stride`), every row started.
  [[nodiscard]] row_runs finish(const void* data, int width, int height,
                                std::ptrdiff_t stride) const noexcept {
    first_[static_cast<std::size_t>(height)] = static_cast<std::uint32_t>(count_);
    row_runs out;
    out.data_ = data;
    out.width_ = width;
    out.height_ = height;
    out.stride_ = stride;
    out.first_ = first_;
    out.runs_ = runs_;
    return out;
  }

 private:
  std::uint32_t* first_ = nullptr;
  row_run* runs_ = nullptr;
  std::size_t count_ = 0;
  std::size_t max_ = 0;
};

/// Rewrites a run list in place, front to back (`fill_small_holes` joining runs across the
/// gaps it fills): run `at` is put or the last one put extended, and each row's start is set
/// once its runs are written. The list must only shrink (a run is put at or before where it
/// was read).
class run_list_joiner {
 public:
  static void put(row_runs& runs, std::size_t at, row_run run) noexcept { runs.runs_[at] = run; }
  static void extend_last(row_runs& runs, std::size_t count, int end) noexcept {
    PERCH_ASSERT(count > 0, "run_list_joiner: no run to extend");
    runs.runs_[count - 1].end = end;
  }
  static void set_row_start(row_runs& runs, int y, std::size_t at) noexcept {
    runs.first_[static_cast<std::size_t>(y)] = static_cast<std::uint32_t>(at);
  }
};

}  // namespace detail

/// The foreground runs of `mask` (non-zero pixels), at most `max_runs` of them.
///
/// Errors: view errors of `mask`; `capacity_exceeded` (with `error::needed` = max_runs + 1) when
/// the mask has more runs, `workspace_too_small` / `out_of_memory` from the workspace; on any
/// error the workspace is as it was. Complexity: one read of the mask, eight background bytes
/// per step; O(runs) writes.
template <BinaryView Mask>
[[nodiscard]] result<row_runs> find_row_runs(const Mask& mask, workspace& ws,
                                             std::size_t max_runs) noexcept {
  PERCH_TRY(validate(mask));
  const int w = mask.width();
  const int h = mask.height();
  const auto entry = ws.mark();
  auto list = detail::run_list_builder::make(ws, h, max_runs);
  PERCH_TRY(all_ok(list));
  for (int y = 0; y < h; ++y) {
    list->start_row(y);
    bool full = false;  // `add` adds nothing once the list is full
    detail::for_each_run_between(detail::row_pointer(mask, y), 0, w,
                                 [&](int a, int b) { full = !list->add(a, b) || full; });
    if (full) {
      ws.rewind(entry);
      return fail(errc::capacity_exceeded, "find_row_runs", max_runs + 1);
    }
  }
  return list->finish(static_cast<const void*>(mask.data()), w, h, mask.stride());
}

namespace detail {

/// How many runs of tree `find_perch` lists for a `width` × `height` box (`row_runs`): one per
/// 16 pixels and one per row; a tree with more (speckle) is scanned instead of listed.
[[nodiscard]] constexpr std::size_t max_runs(std::size_t box_pixels, int height) noexcept {
  return box_pixels / 16 + static_cast<std::size_t>(height);
}
[[nodiscard]] constexpr std::size_t max_runs(int width, int height) noexcept {
  return max_runs(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), height);
}

/// `runs` when they are the runs of `mask` (`row_runs::describes`), else nullptr: the kernels
/// that take runs scan the image themselves for any other.
template <ImageView V>
[[nodiscard]] const row_runs* runs_of(const row_runs* runs, const V& mask) noexcept {
  return runs != nullptr && runs->describes(mask) ? runs : nullptr;
}

/// Calls `visit(a, b)` for each run [a, b) of foreground of row `y` of an image whose row starts
/// at `row` and is `width` pixels wide: from `runs` when given (they must describe the image),
/// else by scanning the row.
template <class T, class Visit>
inline void for_each_run_in_row(const row_runs* runs, int y, const T* row, int width,
                                Visit&& visit) noexcept {
  if (runs != nullptr) {
    for (const row_run r : runs->row(y)) visit(static_cast<int>(r.begin), static_cast<int>(r.end));
    return;
  }
  for_each_run_between(row, 0, width, visit);
}

/// A position in a row's runs, moved left to right: one per neighbouring row while the runs of
/// a row are visited in order, so each neighbour's runs are read once per row.
struct run_cursor {
  std::span<const row_run> runs;
  std::size_t at = 0;
  /// Skips the runs that end at or before x; then `runs[at]`, if any, ends after x.
  void pass(int x) noexcept {
    while (at < runs.size() && runs[at].end <= x) ++at;
  }
};

/// Calls `visit(from, to)` for each stretch [from, to) of [lo, hi), left to right, not in any
/// run of `c` (its gaps). Calls for the same row must come with increasing `lo`.
template <class Visit>
inline void for_each_gap(run_cursor& c, int lo, int hi, Visit&& visit) noexcept {
  int x = lo;
  while (x < hi) {
    c.pass(x);
    if (c.at == c.runs.size()) break;
    const int begin = c.runs[c.at].begin;
    if (begin > x) visit(x, begin < hi ? begin : hi);
    x = c.runs[c.at].end;
  }
  if (x < hi) visit(x, hi);
}

/// Calls `visit(x)` for each x of [lo, hi), left to right, that is not in a run of both `a`
/// and `b` (on a row between them: the pixels with background above or below). Calls for the
/// same row must come with increasing `lo`.
template <class Visit>
inline void for_each_uncovered(run_cursor& a, run_cursor& b, int lo, int hi,
                               Visit&& visit) noexcept {
  int x = lo;
  while (x < hi) {
    a.pass(x);
    b.pass(x);
    if (a.at == a.runs.size() || b.at == b.runs.size()) break;
    const row_run ra = a.runs[a.at];
    const row_run rb = b.runs[b.at];
    const int begin = ra.begin > rb.begin ? ra.begin : rb.begin;
    const int end = ra.end < rb.end ? ra.end : rb.end;
    if (begin >= end) {  // apart: the one ending first meets nothing more of the other
      ++(ra.end < rb.end ? a.at : b.at);
      continue;
    }
    for (const int stop = begin < hi ? begin : hi; x < stop; ++x) visit(x);
    x = end > x ? end : x;
  }
  for (; x < hi; ++x) visit(x);
}

}  // namespace detail

}  // namespace perch
