// SPDX-License-Identifier: BSL-1.0
/// \file
/// `label_components`: connected-component labelling of a binary mask, numbered like
/// `scipy.ndimage.label`, optionally with each component's area and bounding box.
#pragma once

#include <concepts>
#include <cstddef>
#include <cstdint>

#include "perch/core/bounded_vector.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/result.hpp"
#include "perch/core/union_find.hpp"
#include "perch/core/workspace.hpp"
#include "perch/label/connectivity.hpp"
#include "perch/label/detail/scan.hpp"

namespace perch {

/// Area and inclusive bounding box of one labelled component, in pixels.
struct component_stats {
  std::int64_t area;               ///< number of pixels
  int x_min, y_min, x_max, y_max;  ///< inclusive bounding box (x = column, y = row)
};

/// Bytes `label_components` takes from the workspace for a `width` × `height` mask with
/// connectivity `conn`: exactly this, returned to the workspace when the call ends
/// (so `workspace::high_water()` grows by at most this much). 0 for an empty size.
[[nodiscard]] constexpr std::size_t label_workspace_bytes(int width, int height,
                                                          connectivity conn) noexcept {
  if (width <= 0 || height <= 0) return 0;
  return workspace::footprint<std::int32_t>(detail::provisional_label_bound(width, height, conn) +
                                            1);
}

/// Bytes `label_components` takes from the workspace for a `width` × `height` mask with the
/// default connectivity (`eight`). Use the three-argument form for `four`, which needs about
/// twice as much.
[[nodiscard]] constexpr std::size_t label_workspace_bytes(int width, int height) noexcept {
  return label_workspace_bytes(width, height, connectivity::eight);
}

namespace detail {

template <polarity P, BinaryView Mask, MutableImageView Labels>
[[nodiscard]] inline std::int32_t label_first_pass_any(const Mask& mask, const Labels& labels,
                                                       union_find& eq,
                                                       connectivity conn) noexcept {
  if (conn == connectivity::eight)
    label_first_pass<P, connectivity::eight>(mask, labels, eq);
  else
    label_first_pass<P, connectivity::four>(mask, labels, eq);
  return eq.flatten();
}

/// Checks the views and takes the equivalence array from `ws`.
template <BinaryView Mask, MutableImageView Labels>
[[nodiscard]] inline result<union_find> prepare_labelling(const Mask& mask,
                                                                 const Labels& labels,
                                                                 workspace& ws,
                                                                 connectivity conn) noexcept {
  PERCH_TRY(validate_non_empty(mask));
  PERCH_TRY(validate_non_empty(labels));
  PERCH_TRY(same_size(mask, labels));
  if (conn != connectivity::four && conn != connectivity::eight)
    return fail(errc::invalid_parameter, "connectivity");
  const std::size_t bound = provisional_label_bound(mask.width(), mask.height(), conn);
  auto parent = ws.allocate<std::int32_t>(bound + 1);
  PERCH_TRY(all_ok(parent));
  return union_find{parent->data(), 0, static_cast<std::int32_t>(bound)};
}

}  // namespace detail

/// Labels the connected components of `mask` into `labels`: 0 for background, 1..n for the
/// components, numbered in raster order (row by row, left to right) of each component's first
/// pixel — the numbering of `scipy.ndimage.label`. Returns n.
///
/// Algorithm: two-pass labelling with the SAUF decision tree and array-based union-find with
/// path compression (Wu, Otoo & Suzuki, "Optimizing two-pass connected-component labeling
/// algorithms", Pattern Anal. Appl. 12 (2009) 117–135), scanned run by run:
///  1. first pass: each foreground pixel takes a provisional label from its already-scanned
///     neighbours (upper-left, upper, upper-right, left for `eight`; upper, left for `four`),
///     recording equivalences in an int32 array from `ws`; the smaller label is always the root,
///     so each set's root is the label of its component's first pixel;
///  2. the equivalence array is flattened to consecutive final labels in root order;
///  3. second pass: each run of foreground pixels is overwritten with its final label.
///
/// Preconditions: `labels` does not overlap `mask`.
/// Errors: `mask` or `labels` invalid (`null_data`, `stride_too_small`, `bad_dimensions`, ...);
/// `empty_image` for a zero-sized mask; `size_mismatch` when the sizes differ;
/// `invalid_parameter` for a connectivity value outside the enum; `workspace_too_small` (with
/// `needed`) or `out_of_memory` from the workspace. On error `labels` is unspecified.
/// Complexity: O(width · height) time, nearly linear in the number of equivalences (path
/// compression); `label_workspace_bytes(width, height, conn)` bytes of workspace, released
/// before returning. Background pixels are read once per pass and written once.
/// Guarantees: no heap allocation with a sufficient workspace; deterministic; both views may be
/// strided sub-views; any pixel type that converts to bool (non-zero = foreground).
template <BinaryView Mask, MutableImageView Labels>
requires std::same_as<typename Labels::value_type, std::int32_t>
[[nodiscard]] result<std::int32_t> label_components(
    const Mask& mask, const Labels& labels, workspace& ws,
    connectivity conn = connectivity::eight) noexcept {
  const workspace::checkpoint start = ws.mark();
  auto eq = detail::prepare_labelling(mask, labels, ws, conn);
  PERCH_TRY(all_ok(eq));
  const std::int32_t n =
      detail::label_first_pass_any<detail::polarity::foreground>(mask, labels, *eq, conn);
  detail::label_second_pass<detail::polarity::foreground>(mask, labels, *eq,
                                                          [](int, int, int, std::int32_t) {});
  ws.rewind(start);
  return n;
}

/// Like `label_components`, and also fills `stats` with one entry per component: `stats[i]`
/// describes label i + 1 (area in pixels, inclusive bounding box). `stats` is cleared first.
///
/// Errors: those of `label_components`, and `capacity_exceeded` when the mask has more
/// components than `stats.capacity()`: `error::needed` is the number of components, `labels`
/// is still complete and correct, and `stats` is left empty (never truncated).
/// Complexity: as `label_components`, plus O(1) per run of foreground pixels.
template <BinaryView Mask, MutableImageView Labels>
requires std::same_as<typename Labels::value_type, std::int32_t>
[[nodiscard]] result<std::int32_t> label_components(
    const Mask& mask, const Labels& labels, bounded_vector<component_stats>& stats, workspace& ws,
    connectivity conn = connectivity::eight) noexcept {
  stats.clear();
  const workspace::checkpoint start = ws.mark();
  auto eq = detail::prepare_labelling(mask, labels, ws, conn);
  PERCH_TRY(all_ok(eq));
  const std::int32_t n =
      detail::label_first_pass_any<detail::polarity::foreground>(mask, labels, *eq, conn);
  if (static_cast<std::size_t>(n) > stats.capacity()) {
    detail::label_second_pass<detail::polarity::foreground>(mask, labels, *eq,
                                                            [](int, int, int, std::int32_t) {});
    ws.rewind(start);
    return fail(errc::capacity_exceeded, "label_components: stats", static_cast<std::size_t>(n));
  }
  for (std::int32_t i = 0; i < n; ++i)
    (void)stats.push_back({0, mask.width(), mask.height(), -1, -1});
  component_stats* out = stats.begin();
  detail::label_second_pass<detail::polarity::foreground>(
      mask, labels, *eq, [out](int y, int x_begin, int x_end, std::int32_t label) {
        component_stats& s = out[label - 1];
        s.area += x_end - x_begin;
        if (x_begin < s.x_min) s.x_min = x_begin;
        if (x_end - 1 > s.x_max) s.x_max = x_end - 1;
        if (y < s.y_min) s.y_min = y;
        s.y_max = y;
      });
  ws.rewind(start);
  return n;
}

}  // namespace perch
