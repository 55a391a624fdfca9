// SPDX-License-Identifier: BSL-1.0
/// \file
/// The two raster passes of the labeller: a first pass that gives every foreground pixel a
/// provisional label chosen by a decision tree over its already-scanned neighbours, and a second
/// pass that rewrites each run of foreground pixels with its final label.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <utility>

#include "perch/core/image_view.hpp"
#include "perch/core/row_scan.hpp"
#include "perch/core/union_find.hpp"
#include "perch/label/connectivity.hpp"

namespace perch::detail {

/// Which pixels of the mask are labelled: the non-zero ones, or (for counting holes) the zero ones.
enum class polarity : std::uint8_t { foreground, background };

/// True when pixel value `v` is labelled under polarity `P`.
template <polarity P, class V>
[[nodiscard]] constexpr bool is_labelled(const V& v) noexcept {
  if constexpr (P == polarity::foreground) {
    return static_cast<bool>(v);
  } else {
    return !static_cast<bool>(v);
  }
}

/// True when the rows of `Row` are contiguous bytes that can be read many pixels at a time.
template <class Row>
inline constexpr bool byte_row =
    byte_pixels<std::remove_cvref_t<decltype(std::declval<const Row&>()[0])>> &&
    requires(const Row& r) { r.data(); };

/// First x' ≥ x with a labelled pixel in `row` (of `width` pixels), or `width` if none.
/// Byte-sized integral masks with contiguous rows are skipped 16 pixels at a time (`skip_words`).
template <polarity P, class Row>
[[nodiscard]] inline int next_labelled(const Row& row, int x, int width) noexcept {
  if constexpr (byte_row<Row>) x = skip_words<P == polarity::background>(row.data(), x, width);
  while (x < width && !is_labelled<P>(row[static_cast<std::size_t>(x)])) ++x;
  return x;
}

/// End (one past the last pixel) of the run of labelled pixels starting at `x`.
template <polarity P, class Row>
[[nodiscard]] inline int run_end(const Row& row, int x, int width) noexcept {
  if constexpr (byte_row<Row>) x = skip_words<P == polarity::foreground>(row.data(), x, width);
  while (x < width && is_labelled<P>(row[static_cast<std::size_t>(x)])) ++x;
  return x;
}

/// Bound on the provisional labels the first pass issues on a `width` × `height` image.
/// Eight-connectivity: a pixel gets a new label only when its left, upper-left, upper and
/// upper-right neighbours are all unlabelled, so each 2×2 block holds at most one:
/// ⌈w/2⌉·⌈h/2⌉ (Wu et al. 2009, §3). Four-connectivity: only its left and upper neighbours are
/// checked, so at most one of two horizontally adjacent pixels: h·⌈w/2⌉.
[[nodiscard]] constexpr std::size_t provisional_label_bound(int width, int height,
                                                            connectivity conn) noexcept {
  if (width <= 0 || height <= 0) return 0;
  const auto half_w = (static_cast<std::size_t>(width) + 1) / 2;
  const auto half_h = (static_cast<std::size_t>(height) + 1) / 2;
  return conn == connectivity::eight ? half_w * half_h : static_cast<std::size_t>(height) * half_w;
}

/// First pass: writes a provisional label (or 0) into every pixel of `labels` and records label
/// equivalences in `eq`.
///
/// Scans row by row, run by run. The decision tree is the scan-plus-array-based union-find
/// (SAUF) tree of Wu, Otoo & Suzuki 2009 (§2.2, Fig. 3) for eight-connectivity: with the
/// current pixel e, its left neighbour d and its upper neighbours a b c (upper-left, upper,
/// upper-right), e takes b's label if b is set; otherwise if c is set it merges c with a or d;
/// otherwise it takes a's or d's label, or a new one. Inside a run d is set, and since a and b
/// are neighbours of d (already merged with it when d was scanned), the tree reduces to "take
/// d's label; merge with c if c is set and b is not" — the reuse of neighbours examined for the
/// previous pixel that Grana, Baraldi & Bolelli call pixel prediction ("Optimized connected
/// components labeling with pixel prediction", ACIVS 2016).
/// Four-connectivity is the same with neighbours b and d only.
template <polarity P, connectivity Conn, BinaryView Mask, MutableImageView Labels>
inline void label_first_pass(const Mask& mask, const Labels& labels,
                             union_find& eq) noexcept {
  const int width = mask.width();
  const int height = mask.height();
  auto at = [](int x) { return static_cast<std::size_t>(x); };

  // Row 0: every run is a new component so far.
  {
    const auto m = mask.row(0);
    const auto l = labels.row(0);
    int x = 0;
    while (x < width) {
      const int start = next_labelled<P>(m, x, width);
      for (; x < start; ++x) l[at(x)] = 0;
      if (x == width) break;
      const int end = run_end<P>(m, x, width);
      const std::int32_t label = eq.make();
      for (; x < end; ++x) l[at(x)] = label;
    }
  }

  for (int y = 1; y < height; ++y) {
    const auto m = mask.row(y);
    const auto mu = mask.row(y - 1);
    const auto l = labels.row(y);
    const auto lu = labels.row(y - 1);
    auto up = [&](int x) { return is_labelled<P>(mu[at(x)]); };
    int x = 0;
    while (x < width) {
      const int start = next_labelled<P>(m, x, width);
      for (; x < start; ++x) l[at(x)] = 0;
      if (x == width) break;
      const int end = run_end<P>(m, x, width);

      // The run's first pixel e = (start, y): its left neighbour d is not labelled.
      std::int32_t label = 0;
      if constexpr (Conn == connectivity::eight) {
        if (up(start)) {
          label = lu[at(start)];
        } else {
          const bool c = start + 1 < width && up(start + 1);
          const bool a = start > 0 && up(start - 1);
          if (c)
            label = a ? eq.merge(lu[at(start - 1)], lu[at(start + 1)]) : lu[at(start + 1)];
          else
            label = a ? lu[at(start - 1)] : eq.make();
        }
        // The other pixels e = (k − 1, y) of the run: merge with c = (k, y − 1) where b =
        // (k − 1, y − 1) is not labelled, i.e. where a run of the row above starts at k.
        const int last = end < width ? end : width - 1;
        bool previous = start + 2 <= last && up(start + 1);
        for (int k = start + 2; k <= last; ++k) {
          const bool current = up(k);
          if (current && !previous) label = eq.merge(label, lu[at(k)]);
          previous = current;
        }
      } else {
        label = up(start) ? lu[at(start)] : eq.make();
        // The other pixels e = (k, y): merge with b = (k, y − 1) where a run above starts.
        bool previous = up(start);
        for (int k = start + 1; k < end; ++k) {
          const bool current = up(k);
          if (current && !previous) label = eq.merge(label, lu[at(k)]);
          previous = current;
        }
      }
      // Every pixel of the run is in one set; any label of the set will do.
      for (; x < end; ++x) l[at(x)] = label;
    }
  }
}

/// Second pass: rewrites every run of labelled pixels with the final label of its first pixel
/// (all pixels of a run are in one component), after `eq.flatten()`. Background pixels already
/// hold 0 and are skipped without being read. Calls `visit(y, x_begin, x_end, final_label)` per
/// run (for statistics).
template <polarity P, BinaryView Mask, MutableImageView Labels, class Visit>
inline void label_second_pass(const Mask& mask, const Labels& labels, const union_find& eq,
                              Visit&& visit) noexcept {
  const int width = mask.width();
  for (int y = 0; y < mask.height(); ++y) {
    const auto m = mask.row(y);
    const auto l = labels.row(y);
    int x = 0;
    while (true) {
      x = next_labelled<P>(m, x, width);
      if (x == width) break;
      const int end = run_end<P>(m, x, width);
      const std::int32_t label = eq.parent[l[static_cast<std::size_t>(x)]];
      visit(y, x, end, label);
      for (; x < end; ++x) l[static_cast<std::size_t>(x)] = label;
    }
  }
}

}  // namespace perch::detail
