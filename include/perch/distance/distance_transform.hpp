// SPDX-License-Identifier: BSL-1.0
/// \file
/// The exact Euclidean distance transform of a binary mask: for every foreground pixel, the
/// distance to the nearest background pixel centre (Meijster, Roerdink & Hesselink 2000), as
/// squared integers, optionally with the nearest background pixel, or as real distances for
/// anisotropic pixels.
#pragma once

#include <cmath>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

#include "perch/core/geometry.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/prefetch.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/row_scan.hpp"
#include "perch/core/workspace.hpp"
#include "perch/distance/detail/envelope.hpp"

namespace perch {

/// Options of the real-valued distance transform: the physical size of a pixel.
struct distance_options {
  float spacing_x = 1.0f;  ///< width of a pixel (any unit; the distances come out in it), > 0
  float spacing_y = 1.0f;  ///< height of a pixel, > 0

  /// `invalid_parameter` (naming the field) unless both spacings are finite and positive.
  [[nodiscard]] constexpr status validate() const noexcept {
    // (`std::isfinite` is not constexpr: the largest float bounds the finite ones, and a NaN
    // fails both comparisons.)
    constexpr float largest = std::numeric_limits<float>::max();
    if (!(spacing_x > 0.0f && spacing_x <= largest))
      return fail(errc::invalid_parameter, "distance_options.spacing_x");
    if (!(spacing_y > 0.0f && spacing_y <= largest))
      return fail(errc::invalid_parameter, "distance_options.spacing_y");
    return {};
  }
};

/// Bytes of workspace every distance transform of a `width` × `height` mask takes (exact: the
/// sum of `workspace::footprint` of its row buffers; the same for all variants). The memory is
/// given back before the call returns.
[[nodiscard]] constexpr std::size_t distance_workspace_bytes(int width, int height) noexcept {
  if (width <= 0 || height <= 0) return 0;
  const std::size_t n = static_cast<std::size_t>(width) + 2;
  return 6 * workspace::footprint<std::uint32_t>(n) + workspace::footprint<double>(n) +
         workspace::footprint<std::int16_t>(detail::window_scratch(n));
}

namespace detail {

enum class edt_output : std::uint8_t { squared, nearest, real };
/// Whether background pixels of the output are written (0, and themselves as nearest) or left.
enum class edt_background : std::uint8_t { write, leave };

/// The row buffers of `distance_transform_impl`, one entry per column plus the two outside
/// (see `distance_workspace_bytes`).
struct edt_rows {
  std::uint32_t* down;      ///< per column: the run length of foreground above / below
  std::uint32_t* g_int;     ///< a run's column distances (integer outputs)
  float* g_real;            ///< a run's column distances (`edt_output::real`)
  std::int32_t* s;          ///< the lower envelope's parabolas ...
  std::int32_t* t;          ///< ... and where each starts
  std::int32_t* site;       ///< per pixel of a run: its nearest site
  std::int32_t* near_row;   ///< per site: the row of its nearest background pixel
  double* inverse_twice;    ///< 1 / (2 q), filled as far as needed (`fill_inverse_twice`)
  std::int16_t* window;     ///< `nearest_sites_window`'s scratch
  std::size_t inverses_ready = 0;  ///< filled as far as the longest enveloped run so far needs
};

/// `edt_rows` for a `w` × `h` mask from `ws`. Errors: `workspace_too_small` with the bytes a
/// borrowed workspace needs (what is used plus `distance_workspace_bytes`), else
/// `out_of_memory`; `ws` is then as it was.
template <edt_output Out>
[[nodiscard]] result<edt_rows> allocate_edt_rows(workspace& ws, int w, int h) noexcept {
  const auto n = static_cast<std::size_t>(w) + 2;
  const auto entry = ws.mark();
  const std::size_t used_at_entry = ws.used();
  auto down = ws.allocate<std::uint32_t>(n);
  auto g_int = ws.allocate<std::uint32_t>(Out == edt_output::real ? 0 : n);
  auto g_real = ws.allocate<float>(Out == edt_output::real ? n : 0);
  auto s = ws.allocate<std::int32_t>(n);
  auto t = ws.allocate<std::int32_t>(n);
  auto site = ws.allocate<std::int32_t>(n);
  auto near_row = ws.allocate<std::int32_t>(n);
  auto inverse_twice = ws.allocate<double>(n);
  auto window = ws.allocate<std::int16_t>(detail::window_scratch(n));
  if (!all_ok(down, g_int, g_real, s, t, site, near_row, inverse_twice, window)) {
    ws.rewind(entry);
    auto short_of_room = [](const auto& r) {
      return !r && r.error().code == errc::workspace_too_small;
    };
    if (short_of_room(down) || short_of_room(g_int) || short_of_room(g_real) ||
        short_of_room(s) || short_of_room(t) || short_of_room(site) || short_of_room(near_row) ||
        short_of_room(inverse_twice) || short_of_room(window))
      return fail(errc::workspace_too_small, "distance_transform",
                  used_at_entry + distance_workspace_bytes(w, h));
    return fail(errc::out_of_memory, "distance_transform");
  }
  return edt_rows{down->data(), g_int->data(),    g_real->data(),         s->data(),
                  t->data(),    site->data(),     near_row->data(),       inverse_twice->data(),
                  window->data()};
}

/// Phase 1 downwards, on foreground pixels only: the run length of foreground above and
/// including each pixel, kept per column in `dn` (valid where the pixel above is foreground:
/// it was set on the row above) and stored in the output (rows outside the image are
/// background).
template <class Mask, class Dist>
void column_runs_down(const Mask& mask, const Dist& dist, const row_runs* runs, std::uint32_t* dn,
                      bool fetch_ahead) noexcept {
  using D = typename Dist::value_type;
  using M = std::remove_cvref_t<decltype(*row_pointer(mask, 0))>;
  const int w = mask.width();
  const int h = mask.height();
  const M* above = nullptr;
  for (int y = 0; y < h; ++y) {
    const M* m = row_pointer(mask, y);
    D* d = row_pointer(dist, y);
    detail::for_each_run_in_row(runs, y, m, w, [&](int a, int b) {
      // Fetched two rows ahead (the runs there lie mostly under this one): the distances and
      // the mask row above them, which that row reads. (Inline: see prefetch.hpp.)
      if (fetch_ahead && y + 2 < h) {
        detail::prefetch_span(row_pointer(dist, y + 2) + a, b - a);
        detail::prefetch_span(row_pointer(mask, y + 1) + a, b - a);
      }
      for (int x = a; x < b; ++x) {
        const std::uint32_t up = above != nullptr && static_cast<bool>(above[x]) ? dn[x] + 1 : 1;
        dn[x] = up;
        d[x] = static_cast<D>(up);
      }
    });
    above = m;
  }
}

/// Phase 2 of the real-valued transform on the run [a, a + sites − 2) of row `d`: the column
/// distances (scaled by `sy`) enveloped along the row (spacing² `sx2`).
inline void real_distances_of_run(float* d, int a, int sites, edt_rows& rows, double sx2,
                                  float sy) noexcept {
  float* g = rows.g_real;
  const std::uint32_t* dn = rows.down;
  g[0] = 0.0f;
  g[sites - 1] = 0.0f;
  for (int u = 1; u + 1 < sites; ++u) {
    const int c = a - 1 + u;
    const auto up = static_cast<std::uint32_t>(d[c]);
    g[u] = sy * static_cast<float>(up < dn[c] ? up : dn[c]);
  }
  detail::envelope_real(g, sites, sx2, rows.s, rows.t, rows.site);
  for (int u = 1; u + 1 < sites; ++u) {
    const std::int32_t i = rows.site[u];
    const double dx = static_cast<double>(u - i);
    const double gi = static_cast<double>(g[i]);
    d[a - 1 + u] = static_cast<float>(std::sqrt(sx2 * dx * dx + gi * gi));
  }
}

/// Phase 2 of the squared transform on the run [a, a + sites − 2) of row `y` (output `d`;
/// with `edt_output::nearest`, the nearest background pixels into `near_row_out`): a run whose
/// sites all lie near takes the small window, any other the lower envelope.
template <edt_output Out>
void squared_distances_of_run(std::uint32_t* d, pixel* near_row_out, int y, int a, int sites,
                              edt_rows& rows) noexcept {
  std::uint32_t* g = rows.g_int;
  const std::uint32_t* dn = rows.down;
  std::int32_t* nr = rows.near_row;
  g[0] = 0;
  g[sites - 1] = 0;
  std::uint32_t reach = 0;  // see nearest_sites_window
  for (int u = 1; u + 1 < sites; ++u) {
    const int c = a - 1 + u;
    const std::uint32_t up = d[c];
    const bool from_above = up <= dn[c];
    g[u] = from_above ? up : dn[c];
    if constexpr (Out == edt_output::nearest)
      nr[u] = from_above ? y - static_cast<std::int32_t>(up) : y + static_cast<std::int32_t>(dn[c]);
    const auto end_near = static_cast<std::uint32_t>(u < sites - 1 - u ? u : sites - 1 - u);
    const std::uint32_t r = g[u] < end_near ? g[u] : end_near;
    reach = r > reach ? r : reach;
  }
  if (Out == edt_output::squared && reach <= static_cast<std::uint32_t>(detail::window_reach_max)) {
    detail::nearest_sites_window(g, sites, static_cast<int>(reach), rows.window, d + (a - 1));
    return;
  }
  const auto needed = static_cast<std::size_t>(sites);
  if (needed > rows.inverses_ready) {
    detail::fill_inverse_twice(rows.inverse_twice, rows.inverses_ready, needed);
    rows.inverses_ready = needed;
  }
  detail::envelope_sq(g, sites, rows.s, rows.t, rows.site, rows.inverse_twice);
  for (int u = 1; u + 1 < sites; ++u) {
    const std::int32_t i = rows.site[u];
    const auto dx = static_cast<std::uint32_t>(u > i ? u - i : i - u);
    d[a - 1 + u] = dx * dx + g[i] * g[i];
    if constexpr (Out == edt_output::nearest) {
      const bool edge = i == 0 || i == sites - 1;
      near_row_out[a - 1 + u] = pixel{a - 1 + i, edge ? y : nr[i]};
    }
  }
}

/// The transform itself; `Out` is the output kind, `near` is used for `edt_output::nearest`.
/// `runs`: the runs of `mask` (see `row_runs`), or nullptr to scan the rows for them.
template <edt_output Out, edt_background Background, class Mask, class Dist, class Near>
[[nodiscard]] status distance_transform_impl(const Mask& mask, const Dist& dist, const Near& near,
                                             workspace& ws, const distance_options& options,
                                             const row_runs* runs = nullptr) noexcept {
  using D = typename Dist::value_type;
  using M = std::remove_cvref_t<decltype(*row_pointer(mask, 0))>;
  const int w = mask.width();
  const int h = mask.height();
  const auto entry = ws.mark();
  auto allocated = allocate_edt_rows<Out>(ws, w, h);
  PERCH_TRY(all_ok(allocated));
  edt_rows& rows = *allocated;
  std::uint32_t* dn = rows.down;

  // Rows are fetched ahead only on large images (see `fetch_ahead_from`).
  const bool fetch_ahead =
      static_cast<std::size_t>(w) * static_cast<std::size_t>(h) >= fetch_ahead_from;
  column_runs_down(mask, dist, runs, dn, fetch_ahead);

  // Phase 1 upwards (the run length below, in `dn` again), then phase 2 on the row: each run
  // of foreground [a, b] sees only the sites a−1 … b+1, because the background at a−1 and b+1
  // (or outside the image) is nearer than anything beyond it.
  const double sx = static_cast<double>(options.spacing_x);
  const double sx2 = sx * sx;
  const float sy = options.spacing_y;
  const M* below = nullptr;
  for (int y = h - 1; y >= 0; --y) {
    const M* m = row_pointer(mask, y);
    D* d = row_pointer(dist, y);
    // Background [from, to) (before a run, or to the row's end): 0, its own nearest pixel.
    auto background = [&](int from, int to) {
      if constexpr (Background == edt_background::write) {
        for (int c = from; c < to; ++c) d[c] = D{0};
        if constexpr (Out == edt_output::nearest) {
          pixel* p = row_pointer(near, y);
          for (int c = from; c < to; ++c) p[c] = pixel{c, y};
        }
      }
    };
    int x = 0;  // the first pixel after the last run
    detail::for_each_run_in_row(runs, y, m, w, [&](int a, int end) {
      if (fetch_ahead && y >= 2) {  // as in phase 1, two rows up
        detail::prefetch_span(row_pointer(dist, y - 2) + a, end - a);
        detail::prefetch_span(row_pointer(mask, y - 1) + a, end - a);
      }
      background(x, a);
      const int b = end - 1;
      for (int c = a; c <= b; ++c)
        dn[c] = below != nullptr && static_cast<bool>(below[c]) ? dn[c] + 1 : 1;
      const int sites = b - a + 3;  // a−1 … b+1
      if constexpr (Out == edt_output::real) {
        real_distances_of_run(d, a, sites, rows, sx2, sy);
      } else {
        pixel* near_out = nullptr;
        if constexpr (Out == edt_output::nearest) near_out = row_pointer(near, y);
        squared_distances_of_run<Out>(d, near_out, y, a, sites, rows);
      }
      x = end;
    });
    background(x, w);
    below = m;
  }
  ws.rewind(entry);
  return {};
}

template <class Mask, class Dist>
[[nodiscard]] constexpr status validate_distance_views(const Mask& mask, const Dist& dist) noexcept {
  PERCH_TRY(validate_non_empty(mask));
  PERCH_TRY(validate(dist));
  PERCH_TRY(same_size(mask, dist));
  return {};
}

}  // namespace detail

/// Squared exact Euclidean distance transform.
///
/// Writes to every pixel of `dist2` the squared distance from that pixel's centre to the
/// nearest background pixel centre: 0 on background, ≥ 1 on foreground (non-zero mask pixels).
/// Pixels outside the image count as background, so a mask touching the border is measured to
/// the border (a foreground pixel in the first row has distance at most 1).
///
/// Method: Meijster, Roerdink & Hesselink, "A general algorithm for computing distance
/// transforms in linear time" (Mathematical Morphology and its Applications to Image and Signal
/// Processing, 2000), the Euclidean case: phase 1 gives each pixel its distance to the nearest
/// background pixel in its column (one pass down, one up); phase 2 takes, along each row, the
/// lower envelope of the parabolas (x − i)² + g(i)². Both work on runs of foreground pixels,
/// found eight mask bytes at a time: phase 1 counts a column's run length only on foreground
/// (a pixel whose upper neighbour is background starts at 1), and a run [a, b] of a row needs
/// only the sites a−1 … b+1 in phase 2 (the background at a−1 and b+1 is nearer than any site
/// beyond it; a run whose every pixel has its nearest site within 64 columns, as where the row
/// crosses thin limbs, takes the minimum over that window of sites instead, eight pixels per
/// SSE2 step, with the same result). So only the mask is read whole; the rest costs
/// O(foreground).
///
/// Preconditions: none (bad input is reported). Errors: view errors of `mask` (empty, null
/// data, stride < width, too large) or `dist2`, `size_mismatch` when they differ in size,
/// `workspace_too_small` (with `error::needed`) when a borrowed workspace cannot hold
/// `distance_workspace_bytes(width, height)`.
/// Complexity: two reads of the mask (eight bytes per step through background), O(foreground)
/// for the distances, one write per background pixel; no allocation beyond the workspace,
/// which is given back on return.
/// Guarantees: exact (integer arithmetic); deterministic; `dist2` ≤ ((min(w, h) + 1) / 2)².
template <BinaryView Mask, MutableImageView Dist>
  requires std::same_as<typename Dist::value_type, std::uint32_t>
[[nodiscard]] status distance_transform_sq(const Mask& mask, const Dist& dist2,
                                           workspace& ws) noexcept {
  PERCH_TRY(detail::validate_distance_views(mask, dist2));
  using detail::edt_background, detail::edt_output;
  return detail::distance_transform_impl<edt_output::squared, edt_background::write>(
      mask, dist2, dist2, ws, distance_options{});
}

/// Squared exact Euclidean distance transform of the foreground only.
///
/// As `distance_transform_sq`, but writes only the foreground pixels of `dist2`: background
/// pixels keep whatever they held. For callers that read distances only on the shape (the
/// skeleton, its graph, `find_perch`), this skips writing a whole image of zeros, most of a
/// thin tree mask's bytes.
/// With `runs` (`find_row_runs` of `mask`), both passes take the runs from the list instead of
/// scanning the mask's rows for them, so the mask is read only next to its runs: the same
/// distances without two scans of the background. Runs that do not `describe` `mask` are
/// ignored; runs of a mask changed since they were found give wrong distances (never a read or
/// write outside the views).
/// Errors and complexity: as `distance_transform_sq`, with O(foreground) writes.
template <BinaryView Mask, MutableImageView Dist>
  requires std::same_as<typename Dist::value_type, std::uint32_t>
[[nodiscard]] status distance_transform_sq_foreground(const Mask& mask, const Dist& dist2,
                                                      workspace& ws,
                                                      const row_runs& runs = {}) noexcept {
  PERCH_TRY(detail::validate_distance_views(mask, dist2));
  using detail::edt_background, detail::edt_output;
  return detail::distance_transform_impl<edt_output::squared, edt_background::leave>(
      mask, dist2, dist2, ws, distance_options{}, runs.describes(mask) ? &runs : nullptr);
}

/// Squared Euclidean distance transform plus, for every pixel, its nearest background pixel.
///
/// As the other overload, and writes to `nearest` the position of a nearest background pixel:
/// the pixel itself on background; on foreground, possibly a pixel just outside the image
/// (x = −1 or width, y = −1 or height) when the border is nearest. Ties are broken by a fixed
/// rule: the smallest column, then the smallest row; so the output is deterministic and
/// (nearest.x − x)² + (nearest.y − y)² == dist2 everywhere.
/// Errors: as the other overload, plus view errors and `size_mismatch` of `nearest`.
/// Complexity: as the other overload, plus one write per pixel of `nearest`.
template <BinaryView Mask, MutableImageView Dist, MutableImageView Nearest>
  requires std::same_as<typename Dist::value_type, std::uint32_t> &&
           std::same_as<typename Nearest::value_type, pixel>
[[nodiscard]] status distance_transform_sq(const Mask& mask, const Dist& dist2,
                                           const Nearest& nearest, workspace& ws) noexcept {
  PERCH_TRY(detail::validate_distance_views(mask, dist2));
  PERCH_TRY(validate(nearest));
  PERCH_TRY(same_size(mask, nearest));
  using detail::edt_background, detail::edt_output;
  return detail::distance_transform_impl<edt_output::nearest, edt_background::write>(
      mask, dist2, nearest, ws, distance_options{});
}

/// Euclidean distance transform for anisotropic pixels, as real distances.
///
/// Writes to every pixel of `dist` the distance, in the unit of `options.spacing_x/y`, from the
/// pixel's centre to the nearest background pixel centre, where pixel centres lie
/// `spacing_x` apart along a row and `spacing_y` apart along a column (0 on background;
/// outside the image counts as background). With unit spacing, `dist` = √`dist2` of
/// `distance_transform_sq` up to float rounding.
/// Method: Meijster et al. 2000 as above; phase 1 scales the column distances by `spacing_y`,
/// phase 2 takes the envelope of spacing_x²·(x − i)² + g(i)² in double precision.
/// Errors: as `distance_transform_sq`; `invalid_parameter` naming the field for a spacing that
/// is not finite and positive; `image_too_large` for a mask taller than 2^24 rows (column run
/// lengths are kept in the float output while phase 1 runs).
/// Complexity: as `distance_transform_sq`.
template <BinaryView Mask, MutableImageView Dist>
  requires std::same_as<typename Dist::value_type, float>
[[nodiscard]] status distance_transform(const Mask& mask, const Dist& dist, workspace& ws,
                                        const distance_options& options = {}) noexcept {
  PERCH_TRY(options.validate());
  PERCH_TRY(detail::validate_distance_views(mask, dist));
  if (mask.height() > (1 << 24)) return fail(errc::image_too_large, "distance_transform: height");
  using detail::edt_background, detail::edt_output;
  return detail::distance_transform_impl<edt_output::real, edt_background::write>(mask, dist, dist,
                                                                                  ws, options);
}

}  // namespace perch
