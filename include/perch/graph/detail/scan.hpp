// SPDX-License-Identifier: BSL-1.0
/// \file
/// Private: visiting the non-zero pixels of a binary view in raster order, skipping runs of
/// zero bytes 32 at a time when the pixels are bytes (skeletons are sparse).
#pragma once

#include <cstdint>
#include <cstring>
#include <type_traits>

#include "perch/core/image_view.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/row_scan.hpp"

namespace perch::detail {

/// Calls `f(x, y)` for every non-zero pixel in [from, to) of row `y` of `view`, left to right,
/// skipping zero bytes 32 at a time when the pixels are bytes (skeletons are sparse).
template <BinaryView V, class F>
constexpr void for_each_set_pixel_in_row(const V& view, int y, int from, int to, F&& f) noexcept {
  using value = typename V::value_type;
  const auto row = view.row(y);
  int x = from;
  if constexpr (byte_pixels<value>) {
    if (!std::is_constant_evaluated()) {
      const auto* bytes = reinterpret_cast<const unsigned char*>(row.data());
      auto word_at = [&](int at) {
        std::uint64_t word = 0;
        std::memcpy(&word, bytes + at, sizeof word);
        return word;
      };
      auto visit = [&](int at, std::uint64_t word) {
        for_each_set_byte(word, [&](int i) { f(at + i, y); });
      };
      // Four words tested at once.
      for (; x + 32 <= to; x += 32) {
        const std::uint64_t a = word_at(x), b = word_at(x + 8);
        const std::uint64_t c = word_at(x + 16), d = word_at(x + 24);
        if ((a | b | c | d) == 0) continue;
        visit(x, a);
        visit(x + 8, b);
        visit(x + 16, c);
        visit(x + 24, d);
      }
      for (; x + 8 <= to; x += 8) visit(x, word_at(x));
    }
  }
  for (; x < to; ++x)
    if (static_cast<bool>(row[static_cast<std::size_t>(x)])) f(x, y);
}

/// Calls `f(x, y)` for every non-zero pixel of `view`, row by row, left to right.
template <BinaryView V, class F>
constexpr void for_each_set_pixel(const V& view, F&& f) noexcept {
  for (int y = 0; y < view.height(); ++y) for_each_set_pixel_in_row(view, y, 0, view.width(), f);
}

/// As `for_each_set_pixel`, reading only the runs `within` (which must `span` the view and
/// contain all its non-zero pixels).
template <BinaryView V, class F>
void for_each_set_pixel_in(const V& view, const row_runs& within, F&& f) noexcept {
  for (int y = 0; y < view.height(); ++y)
    for (const row_run r : within.row(y)) for_each_set_pixel_in_row(view, y, r.begin, r.end, f);
}

/// Calls `f(x, y)` for every skeleton pixel in raster order: inside `runs` when given (they
/// contain the skeleton), else over the whole view.
template <BinaryView Skeleton, class F>
void for_each_skeleton_pixel(const Skeleton& skeleton, const row_runs* runs, F&& f) noexcept {
  if (runs != nullptr) {
    for_each_set_pixel_in(skeleton, *runs, f);
  } else {
    for_each_set_pixel(skeleton, f);
  }
}

/// The number of non-zero pixels of `view` (inside `within` when given: it must `span` the view
/// and contain all its non-zero pixels), 16 byte pixels at a time.
template <BinaryView V>
[[nodiscard]] std::size_t count_set_pixels(const V& view, const row_runs* within) noexcept {
  std::size_t n = 0;
  if constexpr (byte_pixels<typename V::value_type>) {
    for (int y = 0; y < view.height(); ++y) {
      const auto* row = row_pointer(view, y);
      if (within == nullptr) {
        n += count_nonzero(row, view.width());
        continue;
      }
      for (const row_run r : within->row(y)) n += count_nonzero(row + r.begin, r.end - r.begin);
    }
  } else {
    for_each_skeleton_pixel(view, within, [&n](int, int) { ++n; });
  }
  return n;
}

}  // namespace perch::detail
