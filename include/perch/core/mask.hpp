// SPDX-License-Identifier: BSL-1.0
/// \file
/// Preparing a tree mask for analysis: the tree's bounding box, and a binarised, optionally
/// area-downscaled copy of just that box with a one-pixel background border, so every later
/// stage works on the tree's pixels only and reads 3×3 neighbourhoods without bounds checks.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <span>

#include "perch/core/geometry.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/row_scan.hpp"
#include "perch/core/workspace.hpp"

namespace perch {

/// How far a mask's outline may lie from the limb's true surface, per side, in image pixels at
/// the window's scale: a segmenter over- or under-draws a limb by about a pixel, and drawing
/// rounds each outline by up to half of one. A width or a gap read off a mask is good to twice
/// this (`width_uncertainty_px`), so the rules that hold one against a limit (a twig's width
/// in `obstacle_options`, the grasp range in `resolved_diameter`, the claw's reach in
/// `clearance`) ask for that much margin. Half a pixel per side (the drawing's rounding alone)
/// was right on perch's own synthetic masks, but on the same trees drawn a pixel wider
/// (`perch eval --population arcs:200,colonisation:200 --outline-bias 1`) 65 of 214 perches
/// were wrong (limbs under the grasp range read inside it), and a pixel narrower 32 of 156 (a
/// limb read as a twig); a pixel per side: 27 of 193 and 14 of 118, and 17 of 144 on the
/// masks as drawn (16 of 188).
inline constexpr float outline_uncertainty_px = 1.0f;
/// A width or gap between two outlines read off a mask is good to this many pixels.
inline constexpr float width_uncertainty_px = 2.0f * outline_uncertainty_px;

/// An inclusive pixel rectangle; `empty()` when it holds no pixel.
struct pixel_box {
  int x_min = 0, y_min = 0, x_max = -1, y_max = -1;
  [[nodiscard]] constexpr bool empty() const noexcept { return x_max < x_min || y_max < y_min; }
  [[nodiscard]] constexpr int width() const noexcept { return empty() ? 0 : x_max - x_min + 1; }
  [[nodiscard]] constexpr int height() const noexcept { return empty() ? 0 : y_max - y_min + 1; }
};

/// The bounding box of the non-zero pixels of `mask` (empty box when there are none).
/// Complexity: at most one pass over the rows, eight bytes at a time for byte masks: the first
/// and last rows with tree are found from the top and the bottom; the rows between are scanned
/// only left of and right of the columns the box spans so far.
template <BinaryView Mask>
[[nodiscard]] pixel_box tree_bounds(const Mask& mask) noexcept {
  const int w = mask.width();
  auto empty_row = [&](int y) { return detail::next_set(detail::row_pointer(mask, y), 0, w) == w; };
  pixel_box box{w, 0, -1, mask.height() - 1};
  while (box.y_min < mask.height() && empty_row(box.y_min)) ++box.y_min;
  if (box.y_min == mask.height()) return {};
  while (empty_row(box.y_max)) --box.y_max;
  for (int y = box.y_min; y <= box.y_max; ++y) {
    const auto* row = detail::row_pointer(mask, y);
    box.x_min = detail::next_set(row, 0, box.x_min);
    box.x_max = detail::last_set(row, box.x_max + 1, w);
  }
  return box;
}

/// The mask as the pipeline analyses it.
///
/// `pixels` is 1 on tree and 0 elsewhere, with a background border of one pixel; `offset` maps
/// its coordinates to the analysed frame (`analysed = local + offset`), and the analysed frame
/// maps to the input image by `input = (analysed + 0.5) / factor − 0.5` (identity at factor 1).
struct prepared_mask {
  image_view<std::uint8_t> pixels{};
  pixel offset{};
  float factor = 1.0f;        ///< analysed size / input size
  int analysed_width = 0;     ///< the whole input image at `factor`
  int analysed_height = 0;
  std::int64_t tree_pixels = 0;  ///< non-zero pixels in `pixels`
  /// The runs of `pixels` when `prepare_mask` was asked to list them (`runs_listing::list`)
  /// and they fit (at most `detail::max_runs` of the box's size); else empty, and the kernels
  /// that take runs scan `pixels` instead. They borrow workspace memory like `pixels`.
  row_runs runs{};

  /// A point of the analysed frame in input-image pixels. Scalar division on purpose: Eigen's
  /// vectorised divide is a reciprocal estimate on 32-bit NEON, and this value is rounded to a
  /// site's pixel, which must be the same on every target.
  [[nodiscard]] point2f to_input(point2f analysed) const noexcept {
    if (factor == 1.0f) return analysed;
    return point2f(input_coordinate(analysed.x()), input_coordinate(analysed.y()));
  }
  [[nodiscard]] float input_coordinate(float analysed) const noexcept {
    return (analysed + 0.5f) / factor - 0.5f;
  }
};

/// Whether `prepare_mask` also lists the row runs of the mask it makes (`prepared_mask::runs`),
/// for the kernels that take them (distance transform, skeletonisers, hole filling, graph).
enum class runs_listing : std::uint8_t {
  skip,  ///< no runs (the default)
  list,  ///< at factor 1 while the input rows are copied, else by a scan of the reduced copy
};

/// What `prepare_mask` does besides the copy.
struct prepare_options {
  runs_listing runs = runs_listing::skip;  ///< whether to list the copy's row runs too
  /// The largest copy to make, in pixels (its border included); 0: any.
  std::size_t max_box_pixels = 0;
};

/// Size of the analysed image for an input dimension at `factor` (at least 1).
[[nodiscard]] constexpr int scaled_extent(int input, float factor) noexcept {
  if (factor == 1.0f) return std::max(1, input);  // a constant expression at full size
  return std::max(1, static_cast<int>(std::ceil(static_cast<double>(input) * static_cast<double>(factor) - 1e-6)));
}

/// Bytes `prepare_mask` takes besides the analysed box when it reduces a box `box_width` input
/// pixels wide by `factor` (0 at factor 1): the column sums, and the spans' weights, first
/// columns and widths.
[[nodiscard]] constexpr std::size_t reduction_workspace_bytes(int box_width, float factor) noexcept {
  if (!(factor < 1.0f)) return 0;
  const auto spans = static_cast<std::size_t>(scaled_extent(box_width, factor) + 3);
  // The input columns under the analysed ones reach up to 1 / factor + 1 past the box.
  const auto reach = static_cast<std::size_t>(std::ceil(1.0 / static_cast<double>(factor)));
  const std::size_t columns = static_cast<std::size_t>(box_width) + 2 * reach + 3;
  return workspace::footprint<float>(columns) + workspace::footprint<double>(columns + spans) +
         workspace::footprint<std::int32_t>(spans) +
         workspace::footprint<std::int32_t>(spans + 1) + workspace::footprint<double>(spans);
}

/// Bytes `prepare_mask` takes from the workspace for a tree box of `box_width` × `box_height`
/// input pixels at `factor` (an upper bound when factor < 1).
[[nodiscard]] constexpr std::size_t prepare_mask_workspace_bytes(int box_width, int box_height,
                                                              float factor = 1.0f) noexcept {
  const auto w = static_cast<std::size_t>(scaled_extent(box_width, factor) + 3);
  const auto h = static_cast<std::size_t>(scaled_extent(box_height, factor) + 3);
  return workspace::footprint<std::uint8_t>(w * h) + reduction_workspace_bytes(box_width, factor);
}

namespace detail {

/// The analysed-frame box covering the input box `box` at `factor`, clipped to the analysed
/// image of `out`.
[[nodiscard]] inline pixel_box analysed_box(const pixel_box& box, float factor,
                                            const prepared_mask& out) noexcept {
  const auto f = static_cast<double>(factor);
  pixel_box a;
  a.x_min = static_cast<int>(std::floor(box.x_min * f));
  a.y_min = static_cast<int>(std::floor(box.y_min * f));
  a.x_max = std::min(out.analysed_width - 1, static_cast<int>(std::ceil((box.x_max + 1) * f)) - 1);
  a.y_max = std::min(out.analysed_height - 1, static_cast<int>(std::ceil((box.y_max + 1) * f)) - 1);
  return a;
}

/// `out.pixels`: the analysed box `a` with a one-pixel border, from `ws`; the border is
/// cleared here, every pixel inside it is written by the caller.
[[nodiscard]] inline status allocate_bordered(const pixel_box& a, workspace& ws,
                                              prepared_mask& out) noexcept {
  const int w = a.width() + 2;
  const int h = a.height() + 2;
  auto pixels = ws.allocate<std::uint8_t>(static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  PERCH_TRY(all_ok(pixels));
  out.pixels = image_view<std::uint8_t>(pixels->data(), w, h);
  out.offset = {a.x_min - 1, a.y_min - 1};
  std::fill_n(&out.pixels(0, 0), w, std::uint8_t{0});
  std::fill_n(&out.pixels(0, h - 1), w, std::uint8_t{0});
  for (int y = 1; y + 1 < h; ++y) out.pixels(0, y) = out.pixels(w - 1, y) = 0;
  return {};
}

/// At factor 1: the box `box` of `mask` binarised into `out.pixels`; returns the tree pixels.
template <BinaryView Mask>
[[nodiscard]] std::int64_t copy_binarised(const Mask& mask, const pixel_box& box,
                                          const prepared_mask& out) noexcept {
  std::int64_t count = 0;
  for (int y = box.y_min; y <= box.y_max; ++y)
    count += binarise_row(row_pointer(mask, y) + box.x_min, &out.pixels(1, y - box.y_min + 1),
                          box.width());
  return count;
}

/// At factor 1, as `copy_binarised`, and the runs listed into `out.runs` on the way: each
/// input row's runs, written as runs of ones into a zeroed row and listed, until the list is
/// full; from there on the rows are binarised (and `out.runs` stays empty, the list's memory
/// given back).
template <BinaryView Mask>
[[nodiscard]] result<std::int64_t> copy_listing_runs(const Mask& mask, const pixel_box& box,
                                                     prepared_mask& out, workspace& ws) noexcept {
  const int w = out.pixels.width();
  const int h = out.pixels.height();
  const auto entry = ws.mark();
  auto list = run_list_builder::make(ws, h, max_runs(w, h));
  PERCH_TRY(all_ok(list));
  std::int64_t count = 0;
  bool listing = true;
  list->start_row(0);
  for (int y = box.y_min; y <= box.y_max; ++y) {
    const auto* row = row_pointer(mask, y);
    std::uint8_t* dst = &out.pixels(0, y - box.y_min + 1);
    if (!listing) {
      count += binarise_row(row + box.x_min, dst + 1, box.width());
      continue;
    }
    list->start_row(y - box.y_min + 1);
    std::fill_n(dst, w, std::uint8_t{0});
    for_each_run_between(row, box.x_min, box.x_max + 1, [&](int a, int b) {
      std::fill_n(dst + (a - box.x_min + 1), b - a, std::uint8_t{1});
      count += b - a;
      listing = listing && list->add(a - box.x_min + 1, b - box.x_min + 1);
    });
  }
  if (listing) {
    list->start_row(h - 1);
    out.runs = list->finish(static_cast<const void*>(out.pixels.data()), w, h,
                            out.pixels.stride());
  } else {
    ws.rewind(entry);
  }
  return count;
}

/// At factor < 1: the analysed box `a` of `mask` reduced by area into `out.pixels`; returns
/// the tree pixels. Accumulates the input rows overlapping each analysed row with their
/// vertical overlap as weight (only their runs of tree), then integrates columns with their
/// horizontal overlap. The columns' spans and overlaps are the same on every row: laid out
/// once (consecutive spans share at most one input column, so they hold at most
/// `columns + spans` weights).
template <BinaryView Mask>
[[nodiscard]] result<std::int64_t> reduce_by_area(const Mask& mask, const pixel_box& a,
                                                  float factor, const prepared_mask& out,
                                                  workspace& ws) noexcept {
  const double inv = 1.0 / static_cast<double>(factor);
  const int in_x0 = static_cast<int>(std::floor(a.x_min * inv));
  const int in_x1 = std::min(mask.width() - 1, static_cast<int>(std::ceil((a.x_max + 1) * inv)));
  const auto columns = static_cast<std::size_t>(in_x1 - in_x0 + 1);
  const auto spans = static_cast<std::size_t>(a.width());
  auto column = ws.allocate<float>(columns);
  auto weight = ws.allocate<double>(columns + spans);
  auto first = ws.allocate<std::int32_t>(spans);      // a span's first input column
  auto start = ws.allocate<std::int32_t>(spans + 1);  // and its first weight
  auto width = ws.allocate<double>(spans);
  PERCH_TRY(all_ok(column, weight, first, start, width));
  auto overlap = [](double a0, double a1, double b0, double b1) {
    return std::max(0.0, std::min(a1, b1) - std::max(a0, b0));
  };
  std::int32_t weights = 0;
  for (std::size_t s = 0; s < spans; ++s) {
    const int ax = a.x_min + static_cast<int>(s);
    const double fx0 = ax * inv;
    const double fx1 = std::min((ax + 1) * inv, static_cast<double>(mask.width()));
    (*width)[s] = fx1 - fx0;
    (*first)[s] = std::max(in_x0, static_cast<int>(fx0));
    (*start)[s] = weights;
    for (int x = (*first)[s]; x <= in_x1 && x < fx1; ++x)
      (*weight)[static_cast<std::size_t>(weights++)] = overlap(fx0, fx1, x, x + 1.0);
  }
  (*start)[spans] = weights;
  std::int64_t count = 0;
  for (int ay = a.y_min; ay <= a.y_max; ++ay) {
    const double fy0 = ay * inv;
    const double fy1 = std::min((ay + 1) * inv, static_cast<double>(mask.height()));
    std::fill(column->begin(), column->end(), 0.0f);
    for (int y = static_cast<int>(fy0); y < mask.height() && y < fy1; ++y) {
      const auto wy = static_cast<float>(overlap(fy0, fy1, y, y + 1.0));
      for_each_run_between(row_pointer(mask, y), in_x0, in_x1 + 1, [&](int b0, int b1) {
        for (int x = b0; x < b1; ++x) (*column)[static_cast<std::size_t>(x - in_x0)] += wy;
      });
    }
    std::uint8_t* dst = &out.pixels(1, ay - a.y_min + 1);
    for (std::size_t s = 0; s < spans; ++s) {
      const float* c = column->data() + ((*first)[s] - in_x0);
      const double* wx = weight->data() + (*start)[s];
      const std::int32_t n = (*start)[s + 1] - (*start)[s];
      double tree = 0;
      for (std::int32_t j = 0; j < n; ++j) tree += wx[j] * static_cast<double>(c[j]);
      const double area = (*width)[s] * (fy1 - fy0);
      const std::uint8_t v = area > 0 && tree >= 0.5 * area ? 1 : 0;
      dst[s] = v;
      count += v;
    }
  }
  return count;
}

}  // namespace detail

/// Binarises the tree's bounding box of `mask` into workspace memory with a one-pixel border,
/// reducing it by `factor` ∈ (0, 1] on the way.
///
/// Reduction is area-based: an analysed pixel is tree when at least half of its footprint in the
/// input (its area, with fractional overlaps at the edges) is tree — thin branches keep their
/// width in proportion instead of vanishing or thickening as with nearest-neighbour sampling.
/// An empty mask gives a 2×2 all-background image and `tree_pixels == 0` (not an error).
/// Errors: view errors of `mask`; `invalid_parameter` for a factor outside (0, 1];
/// `workspace_too_small` / `out_of_memory` from the workspace.
/// `options.runs`: with `runs_listing::list`, the copy's row runs too (`prepared_mask::runs`:
/// found on the input rows while they are copied at factor 1, by a scan of the reduced copy
/// otherwise); a copy with more than `detail::max_runs` of them (speckle) gets none, and the
/// memory of the list is given back. Their bytes are `row_runs_workspace_bytes(height,
/// detail::max_runs(width, height))` of the copy, besides `prepare_mask_workspace_bytes`.
/// `options.max_box_pixels`: a larger copy (border included) is refused with
/// `capacity_exceeded` (`needed`: its pixels) before it takes memory.
/// Complexity: O(box pixels), one pass (and one read of the reduced copy for its runs).
template <BinaryView Mask>
[[nodiscard]] result<prepared_mask> prepare_mask(const Mask& mask, workspace& ws,
                                                 float factor = 1.0f,
                                                 const prepare_options& options = {}) noexcept {
  PERCH_TRY(validate_non_empty(mask));
  if (!(factor > 0.0f && factor <= 1.0f)) return fail(errc::invalid_parameter, "downscale factor");
  prepared_mask out;
  out.factor = factor;
  out.analysed_width = scaled_extent(mask.width(), factor);
  out.analysed_height = scaled_extent(mask.height(), factor);
  const pixel_box box = tree_bounds(mask);
  if (box.empty()) {
    auto pixels = ws.allocate_zeroed<std::uint8_t>(4);
    PERCH_TRY(all_ok(pixels));
    out.pixels = image_view<std::uint8_t>(pixels->data(), 2, 2);
    return out;
  }
  const pixel_box analysed = detail::analysed_box(box, factor, out);
  const auto box_pixels = static_cast<std::size_t>(analysed.width() + 2) *
                          static_cast<std::size_t>(analysed.height() + 2);
  if (options.max_box_pixels != 0 && box_pixels > options.max_box_pixels)
    return fail(errc::capacity_exceeded, "prepare_options.max_box_pixels", box_pixels);
  PERCH_TRY(detail::allocate_bordered(analysed, ws, out));
  const bool list = options.runs == runs_listing::list;
  if (factor == 1.0f && list) {
    auto count = detail::copy_listing_runs(mask, box, out, ws);
    PERCH_TRY(all_ok(count));
    out.tree_pixels = *count;
    return out;
  }
  if (factor == 1.0f) {
    out.tree_pixels = detail::copy_binarised(mask, box, out);
    return out;
  }
  auto count = detail::reduce_by_area(mask, analysed, factor, out, ws);
  PERCH_TRY(all_ok(count));
  out.tree_pixels = *count;
  if (list) {
    const int w = out.pixels.width(), h = out.pixels.height();
    auto found = find_row_runs(image_view<const std::uint8_t>(out.pixels), ws, detail::max_runs(w, h));
    if (!found && found.error().code != errc::capacity_exceeded) return unexpected{found.error()};
    if (found) out.runs = *found;
  }
  return out;
}

}  // namespace perch
