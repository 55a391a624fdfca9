// SPDX-License-Identifier: BSL-1.0
/// \file
/// The default skeleton: a one-pixel-thin, topology-preserving medial axis on the ridges of the
/// distance map, by distance-ordered homotopic thinning.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "perch/core/image_view.hpp"
#include "perch/core/prefetch.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/row_scan.hpp"
#include "perch/core/workspace.hpp"
#include "perch/skeleton/detail/topology.hpp"
#include "perch/skeleton/skeletoniser.hpp"

namespace perch {

/// Medial axis by distance-ordered homotopic thinning (models `Skeletoniser`).
///
/// Method (after Pudney, "Distance-ordered homotopic thinning: a skeletonization algorithm for
/// 3D digital images", Computer Vision and Image Understanding 72(3), 1998, in 2-D):
///  1. Every foreground pixel with a background 4-neighbour enters a bucket queue keyed by its
///     squared distance `dist2` (a monotone bucket queue: linear time).
///  2. Buckets are emptied in increasing `dist2`, each first-in first-out (the initial border in
///     raster order). A popped pixel is deleted when it is *simple* (its deletion keeps the
///     8-components of the tree and the 4-components of the background: Rosenfeld's local
///     test, a 256-entry table) and is not an end pixel (it has at least two 8-neighbours left).
///  3. When a pixel is deleted, its remaining neighbours enter the queue at their own distance,
///     or at the current one if that is lower (they were kept earlier and may be simple now).
///  4. With `thinness::one_pixel`, the clean-up removes any 2×2 block left (e.g. where two
///     diagonal strokes cross).
/// Peeling the shape in order of distance removes the pixels nearest the boundary first, so
/// what survives lies on the ridge of the distance map: on a stroke, the pixels of largest
/// `dist2` across it (one of the two middle rows for an even width), and the diameter there is
/// 2·√dist2 − 1 within a pixel. End pixels are kept, so branches are not shortened beyond the
/// rounding of their tips (a branch ends about one radius inside a square-cut stroke end).
///
/// Guarantees: skeleton ⊆ mask; same 8-connected components and same holes (4-connected
/// background components) as the mask; 8-connected and, by default, one pixel thin (no 2×2
/// block of skeleton pixels, but where the mask leaves no room: `thinness::one_pixel`); every
/// skeleton pixel is an end pixel or not simple, so skeletonising the skeleton gives it back
/// (idempotent); deterministic (ties: distance, then queue order). `dist2` only orders the
/// peeling: any map gives a thin, topology-preserving result; values above the largest
/// distance the image can hold are clamped.
/// Errors: view errors of the three views, `size_mismatch`, `image_too_large` for a strip so
/// thin that its padded copy holds 2^31 pixels, `workspace_too_small` / `out_of_memory` from
/// the workspace (needs `workspace_bytes(width, height)`).
/// Complexity: O(width × height) for the copy in and out (byte sweeps) plus O(foreground) for
/// the peeling; no allocation beyond the workspace, which is given back on return.
struct medial_axis {
  static constexpr std::string_view name = "medial_axis";
  perch::thinness thinness = perch::thinness::one_pixel;  ///< one_pixel (default) or faithful
  /// Working images of at least this many pixels are peeled in a packed copy, two bytes per
  /// pixel holding its flags and its distance together: a neighbourhood's row then takes one
  /// cache line instead of two (flags and distances), which pays once the working set outgrows
  /// the last-level cache, while a smaller image is peeled faster where it lies (the copy costs
  /// more than it saves; timings: docs/performance-log.md). Same skeleton either way.
  std::size_t packed_from = std::size_t{6} << 20;

  /// The largest squared distance a `width` × `height` image can hold: ((min + 1) / 2)².
  [[nodiscard]] static constexpr std::uint32_t max_dist2(int width, int height) noexcept {
    const auto m = static_cast<std::uint32_t>((width < height ? width : height) + 1) / 2;
    return m * m;
  }

  /// Bytes of workspace a call takes at most (the padded working copy and its keys, the
  /// packed copy, the queue: two arrays of a slot per pixel and two per key; then the
  /// clean-up's queue).
  [[nodiscard]] static constexpr std::size_t workspace_bytes(int width, int height) noexcept {
    if (width <= 0 || height <= 0) return 0;
    const std::size_t n = detail::padded_pixels(width, height);
    const std::size_t keys = std::size_t{max_dist2(width, height)} + 2;
    const std::size_t peel = workspace::footprint<std::uint32_t>(n) +
                             2 * workspace::footprint<std::uint32_t>(n + 1) +
                             2 * workspace::footprint<std::uint32_t>(keys) +
                             workspace::footprint<std::uint16_t>(n + packed_slack);
    const std::size_t clean_up = workspace::footprint<std::uint32_t>(n + 16);
    return workspace::footprint<std::uint8_t>(n) + (peel > clean_up ? peel : clean_up);
  }

  /// Bytes a call takes at most on a mask of at most `foreground` pixels within a `width` ×
  /// `height` image that has a background frame, thinned into a skeleton of stride `width`
  /// with `dist2` laid out like it (as `find_perch` calls it: no working copy, distances read
  /// where they are): the peeling's keys, queue and ring and, when it packs, its packed copy;
  /// then the clean-up's queue.
  [[nodiscard]] static constexpr std::size_t framed_workspace_bytes(int width, int height,
                                                                    std::size_t foreground) noexcept {
    if (width <= 0 || height <= 0) return 0;
    const std::size_t cells = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
    const std::size_t peel = workspace::footprint<std::uint32_t>(std::size_t{max_dist2(width, height)} + 2) +
                             workspace::footprint<std::uint32_t>(foreground) +
                             workspace::footprint<std::uint32_t>(foreground + 1) +
                             workspace::footprint<std::uint16_t>(cells + packed_slack);
    const std::size_t clean_up = workspace::footprint<std::uint32_t>(cells + 16);
    return peel > clean_up ? peel : clean_up;
  }

  [[nodiscard]] status operator()(image_view<const std::uint8_t> mask,
                                  image_view<const std::uint32_t> dist2,
                                  image_view<std::uint8_t> skeleton, workspace& ws) const noexcept {
    return (*this)(mask, dist2, skeleton, ws, row_runs{});
  }
  /// With the row runs of `mask` (see `RowRunSkeletoniser`): the same skeleton, the border
  /// pixels and keys found from the runs, and the clean-up scanning only them.
  [[nodiscard]] status operator()(image_view<const std::uint8_t> mask,
                                  image_view<const std::uint32_t> dist2,
                                  image_view<std::uint8_t> skeleton, workspace& ws,
                                  const row_runs& runs) const noexcept {
    PERCH_TRY(detail::validate_skeleton_views(mask, dist2, skeleton));
    const auto entry = ws.mark();
    const status s = run(mask, dist2, skeleton, ws, detail::runs_of(&runs, mask));
    ws.rewind(entry);
    return s;
  }

 private:
  static constexpr std::uint8_t queued = 2;  ///< flag of a pixel in the queue (bit 1 of `px`)
  static constexpr std::uint32_t packed_key_max = 0x3FFF;  ///< packed keys from here: look up
  static constexpr std::size_t packed_slack = 2;  ///< a row of 4 cells read from the last pixel

  /// The key of a distance: the distance, clamped to `cap`.
  [[nodiscard]] static std::uint32_t key_of(std::uint32_t dist2, std::uint32_t cap) noexcept {
    return dist2 < cap ? dist2 : cap;
  }

  /// What the peeling reads and writes of a pixel, in the working image (flags: bit 0
  /// foreground, bit 1 `queued`) and the keys where they are.
  struct in_image {
    std::uint8_t* px;
    std::ptrdiff_t stride;
    const std::uint32_t* keys;
    std::uint32_t cap;
    /// Neighbour k's flags in bits 2k, 2k + 1 (see `padded_image::pairs`).
    [[nodiscard]] unsigned pairs(std::uint32_t i) const noexcept {
      return detail::neighbour_pairs(px + i, stride);
    }
    void keep(std::uint32_t i) const noexcept { px[i] = 1; }
    void erase(std::uint32_t i) const noexcept { px[i] = 0; }
    void mark(std::ptrdiff_t i) const noexcept { px[i] |= queued; }
    [[nodiscard]] std::uint32_t key(std::ptrdiff_t i) const noexcept {
      return key_of(keys[i], cap);
    }
    /// The cache lines a visit of `i` reads (to fetch ahead).
    [[nodiscard]] std::array<const void*, 6> lines(std::uint32_t i) const noexcept {
      return {px + i - stride,   px + i,   px + i + stride,
              keys + i - stride, keys + i, keys + i + stride};
    }
  };
  /// The same in the packed copy: per pixel, the flags in bits 0 and 1 and the key above them
  /// (`packed_key_max` for a key that large or larger: then read from `dist2`).
  template <class Distances>
  struct packed {
    std::uint16_t* cell;
    std::ptrdiff_t stride;
    Distances dist2;
    std::uint32_t cap;
    [[nodiscard]] unsigned pairs(std::uint32_t i) const noexcept {
      // Each row as four cells from the west neighbour's: cell c's flags in bits 16c, 16c + 1.
      std::uint64_t n = 0, m = 0, s = 0;
      std::memcpy(&n, cell + i - stride - 1, sizeof n);
      std::memcpy(&m, cell + i - 1, sizeof m);
      std::memcpy(&s, cell + i + stride - 1, sizeof s);
      return static_cast<unsigned>(((n >> 16) & 0x3u) | ((n >> 30) & 0xCu) | ((m >> 28) & 0x30u) |
                                   ((s >> 26) & 0xC0u) | ((s >> 8) & 0x300u) | ((s & 0x3u) << 10) |
                                   ((m & 0x3u) << 12) | ((n & 0x3u) << 14));
    }
    void keep(std::uint32_t i) const noexcept { cell[i] &= static_cast<std::uint16_t>(~queued); }
    void erase(std::uint32_t i) const noexcept { cell[i] = 0; }
    void mark(std::ptrdiff_t i) const noexcept { cell[i] |= queued; }
    [[nodiscard]] std::uint32_t key(std::ptrdiff_t i) const noexcept {
      const std::uint32_t k = cell[i] >> 2u;
      return k < packed_key_max ? k : key_of(*dist2.run(i), cap);
    }
    [[nodiscard]] std::array<const void*, 3> lines(std::uint32_t i) const noexcept {
      return {cell + i - stride, cell + i, cell + i + stride};
    }
  };

  [[nodiscard]] status run(image_view<const std::uint8_t> mask,
                           image_view<const std::uint32_t> dist2,
                           image_view<std::uint8_t> skeleton, workspace& ws,
                           const row_runs* runs) const noexcept {
    // Fast path: a mask with a background frame (as `prepare_mask` makes) is thinned in the
    // output itself, and when `dist2` is laid out like the output its values are read by index.
    const bool in_place = detail::has_background_frame(mask) &&
                          skeleton.stride() <= static_cast<std::ptrdiff_t>(mask.width()) + 2;
    // The working image's pixels, frame included (in place: the output's rows).
    const std::size_t cells = in_place ? static_cast<std::size_t>(skeleton.stride()) *
                                             static_cast<std::size_t>(mask.height())
                                       : detail::padded_pixels(mask.width(), mask.height());
    const bool packing = cells >= packed_from;
    detail::padded_image img;
    if (in_place) {
      // A packed peeling from listed runs writes the output whole when it copies the skeleton
      // back (zeros around the runs), so the mask is not loaded into it first.
      const bool load = runs == nullptr || !packing || cells >= 0x7FFFFFFFu;
      img = detail::load_in_place(mask, skeleton, runs, load);
    } else {
      auto loaded = detail::load_padded(mask, ws);
      PERCH_TRY(all_ok(loaded));
      img = *loaded;
    }
    img.runs = runs;
    const std::uint32_t cap = max_dist2(img.width, img.height);
    // Pixel indices are held in 32 bits (only a degenerate strip, e.g. 1 × 2^31, has more).
    if (cells >= 0x7FFFFFFFu) return fail(errc::image_too_large, "medial_axis: too many pixels");
    const auto peeling = ws.mark();
    const status peeled =
        in_place && dist2.stride() == img.stride
            ? peel(img, cells, ws, cap, distances_by_index{dist2.data()}, packing)
            : peel(img, cells, ws, cap, distances_by_position{&img, dist2}, packing);
    ws.rewind(peeling);
    if (!peeled) return peeled;
    if (thinness == perch::thinness::one_pixel) {
      auto queue = ws.allocate<std::uint32_t>(cells + 16);
      PERCH_TRY(all_ok(queue));
      (void)detail::remove_blocks(img, mask, dist2, queue->data());
    }
    if (!in_place) detail::store_skeleton(img, skeleton);
    return {};
  }

  /// Where the distances of a run of the working image starting at pixel `i` are: at the same
  /// index when `dist2` is laid out like the working image, else found from the run's position
  /// (a run lies in one row of both images), and then, for the byte image's peeling, copied
  /// into an array laid out like the working image to be read by index.
  struct distances_by_index {
    const std::uint32_t* d;
    static constexpr bool copied = false;
    [[nodiscard]] const std::uint32_t* run(std::ptrdiff_t i) const noexcept { return d + i; }
  };
  struct distances_by_position {
    const detail::padded_image* img;
    image_view<const std::uint32_t> dist2;
    static constexpr bool copied = true;
    [[nodiscard]] const std::uint32_t* run(std::ptrdiff_t i) const noexcept {
      const pixel p = img->position(i);
      return &dist2(p.x, p.y);
    }
  };

  /// The monotone bucket queue, without links: a pixel pushed before its key's turn goes to
  /// that key's slice of `order` (slices laid out by counting the keys of all pixels: each
  /// pixel enters its own key's slice at most once), and one pushed during the key being
  /// emptied, which is appended last anyway, goes to the `ring` (first in, first out). So a
  /// key's pixels are visited in the order a single first-in first-out list would give: the
  /// slice, then the ring; and the pixels to come sit in an array, fetched well ahead.
  /// A queued pixel carries the `queued` flag; a pixel popped and kept re-enters at the current
  /// key when a neighbour is deleted (its own is not above it). With `packing`, the flags and
  /// keys are read and written in a packed copy, and the result copied back at the end.
  /// `cells`: the working image's pixels, frame included.
  template <class Distances>
  [[nodiscard]] static status peel(const detail::padded_image& img, std::size_t cells,
                                   workspace& ws, std::uint32_t cap, Distances distances,
                                   bool packing) noexcept {
    std::uint8_t* px = img.px;
    const std::size_t ring_size = img.pixels + 1;  // more than can be queued at once
    auto fill_memory = ws.allocate<std::uint32_t>(std::size_t{cap} + 2);
    auto order_memory = ws.allocate<std::uint32_t>(img.pixels);
    auto ring_memory = ws.allocate<std::uint32_t>(ring_size);
    auto packed_memory = ws.allocate<std::uint16_t>(packing ? cells + packed_slack : 0);
    PERCH_TRY(all_ok(fill_memory, order_memory, ring_memory, packed_memory));
    std::uint32_t* fill = fill_memory->data();  // per key: the end of its slice so far
    std::uint32_t* order = order_memory->data();
    std::uint32_t* ring = ring_memory->data();
    std::uint16_t* cell = packing ? packed_memory->data() : nullptr;
    // The byte image's peeling reads the distances by index: copied if need be.
    std::uint32_t* copy = nullptr;
    if (Distances::copied && !packing) {
      auto copy_memory = ws.allocate<std::uint32_t>(cells);
      PERCH_TRY(all_ok(copy_memory));
      copy = copy_memory->data();
    }
    const std::uint32_t* keys = copy;
    if constexpr (!Distances::copied) keys = distances.d;
    key_census<Distances> census{distances, keys, copy, cell, fill, ring, cells, img.stride, cap};
    fill[0] = 0;
    fill[1] = 0;
    if (img.runs != nullptr && cell != nullptr)
      census_from_runs(img, census);
    else
      census_from_image(img, census);
    const std::uint32_t top_key = census.top_key;
    auto start_memory = ws.allocate<std::uint32_t>(std::size_t{top_key} + 1);
    PERCH_TRY(all_ok(start_memory));
    std::uint32_t* start = start_memory->data();  // per key: the beginning of its slice
    for (std::uint32_t k = 0; k <= top_key; ++k) {
      fill[k + 1] += fill[k];
      start[k] = fill[k];
    }
    const slices queue{fill, start, order, ring, ring_size, top_key};
    if (cell == nullptr) {
      drain(in_image{px, img.stride, keys, cap}, img, queue, census.border);
      return {};
    }
    drain(packed<Distances>{cell, img.stride, distances, cap}, img, queue, census.border);
    copy_back_packed(img, cell, cells);
    return {};
  }

  /// The first pass of `peel`, one run at a time: the keys counted (into fill[k + 1]; copied,
  /// packed if need be) and the border pixels listed in raster order (in `ring`, for now):
  /// each run's two ends, and between them the pixels below or above background.
  /// The packed copy is read at the tree pixels and their neighbours only: around a run, the
  /// row below is zeroed (its runs come later), the row above where it is background, the
  /// two ends, and then the run's own cells are filled.
  template <class Distances>
  struct key_census {
    Distances distances;
    const std::uint32_t* keys;  ///< the distances by index (when not copied)
    std::uint32_t* copy;        ///< the distances copied by index, or null
    std::uint16_t* cell;        ///< the packed copy, or null
    std::uint32_t* fill;
    std::uint32_t* ring;
    std::size_t cells;
    std::ptrdiff_t s;  ///< the working image's stride
    std::uint32_t cap;
    std::uint32_t top_key = 0;
    std::size_t border = 0;

    /// Counts the keys of the run [first, end) and lists its first pixel.
    void count_run(std::ptrdiff_t first, std::ptrdiff_t end) noexcept {
      const std::uint32_t* d = distances.run(first);
      // Fetched ahead (the runs a few rows down lie mostly under this one): the distances two
      // rows down, read by index, and the packed cells three rows down, first written from
      // two rows down. (Plain loops: with `prefetch_span` here this visitor was no longer
      // inlined, and the pass was slower.)
      if (static_cast<std::size_t>(end + 3 * s + 1) < cells) {
        if constexpr (!Distances::copied)
          for (std::ptrdiff_t i = first + 2 * s; i < end + 2 * s; i += 16)
            detail::prefetch(keys + i);
        if (cell != nullptr)
          for (std::ptrdiff_t i = first + 3 * s - 1; i <= end + 3 * s; i += 32)
            detail::prefetch(cell + i);
      }
      if (cell != nullptr) {
        for (std::ptrdiff_t i = first + s - 1; i <= end + s; ++i) cell[i] = 0;
        cell[first - 1] = 0;
        cell[end] = 0;
      }
      // The run's keys: copied or packed and their largest found first (loops the compiler
      // vectorises), then counted: faster on large images than one loop doing all. (Locals: a
      // store to `fill` could change what a reference points at.)
      const std::ptrdiff_t n = end - first;
      const std::uint32_t c = cap;
      if (copy != nullptr)
        for (std::ptrdiff_t j = 0; j < n; ++j) copy[first + j] = d[j];
      std::uint32_t most = 0;
      if (cell != nullptr) {
        std::uint16_t* const packed_run = cell + first;
        for (std::ptrdiff_t j = 0; j < n; ++j) {
          const std::uint32_t k = key_of(d[j], c);
          most = k > most ? k : most;
          packed_run[j] =
              static_cast<std::uint16_t>((k < packed_key_max ? k : packed_key_max) << 2u | 1u);
        }
      } else {
        for (std::ptrdiff_t j = 0; j < n; ++j) {
          const std::uint32_t k = key_of(d[j], c);
          most = k > most ? k : most;
        }
      }
      std::uint32_t top = top_key;
      while (top < most) fill[++top + 1] = 0;
      top_key = top;
      std::uint32_t* const count = fill + 1;
      for (std::ptrdiff_t j = 0; j < n; ++j) ++count[key_of(d[j], c)];
      ring[border++] = static_cast<std::uint32_t>(first);
    }
    void list(std::ptrdiff_t i) noexcept { ring[border++] = static_cast<std::uint32_t>(i); }
    /// Lists the run's last pixel (unless it is its first).
    void list_last(std::ptrdiff_t first, std::ptrdiff_t end) noexcept {
      if (end - 1 > first) list(end - 1);
    }
  };

  /// `key_census` from the run lists: the background above a run and the pixels covered
  /// above and below are found from the runs of the rows next to it, without reading those
  /// rows (which, on an image large enough to be packed, are out of cache; on a byte image,
  /// small enough to stay in cache, reading them is faster).
  template <class Distances>
  static void census_from_runs(const detail::padded_image& img,
                               key_census<Distances>& census) noexcept {
    const std::ptrdiff_t s = img.stride;
    std::uint16_t* const cell = census.cell;
    const std::span<const row_run> none{};
    for (int y = 0; y < img.height; ++y) {
      const std::ptrdiff_t row = img.index(0, y);
      detail::run_cursor above{y > 0 ? img.runs->row(y - 1) : none};
      detail::run_cursor up{above.runs};
      detail::run_cursor down{y + 1 < img.height ? img.runs->row(y + 1) : none};
      for (const row_run r : img.runs->row(y)) {
        const std::ptrdiff_t first = row + r.begin;
        const std::ptrdiff_t end = row + r.end;
        detail::for_each_gap(above, r.begin - 1, r.end + 1, [&](int from, int to) {
          std::memset(cell + row - s + from, 0, sizeof *cell * static_cast<std::size_t>(to - from));
        });
        census.count_run(first, end);
        detail::for_each_uncovered(up, down, r.begin + 1, r.end - 1,
                                   [&](int x) { census.list(row + x); });
        census.list_last(first, end);
      }
    }
  }

  /// `key_census` from the working image: the rows above and below read eight pixels at a
  /// time.
  template <class Distances>
  static void census_from_image(const detail::padded_image& img,
                                key_census<Distances>& census) noexcept {
    const std::ptrdiff_t s = img.stride;
    const std::uint8_t* const px = img.px;
    std::uint16_t* const cell = census.cell;
    detail::for_each_run(img, [&](std::ptrdiff_t first, std::ptrdiff_t end) {
      if (cell != nullptr)
        for (std::ptrdiff_t i = first - s - 1; i <= end - s; ++i)
          cell[i] = static_cast<std::uint16_t>(cell[i] & (0u - (px[i] & 1u)));
      census.count_run(first, end);
      const std::ptrdiff_t last = end - 1;
      std::ptrdiff_t i = first + 1;
      for (; i + 8 <= last; i += 8) {
        std::uint64_t up = 0, down = 0;
        std::memcpy(&up, px + i - s, 8);
        std::memcpy(&down, px + i + s, 8);
        detail::for_each_set_byte(~(up & down) & 0x0101010101010101ull,
                                  [&](int k) { census.list(i + k); });
      }
      for (; i < last; ++i)
        if (((px[i - s] & px[i + s]) & 1u) == 0) census.list(i);
      census.list_last(first, end);
    });
  }

  /// The skeleton copied back from the packed copy, the cells two rows down fetched ahead as
  /// in the first pass; with the output not loaded, whole rows (zeros between the runs).
  static void copy_back_packed(const detail::padded_image& img, const std::uint16_t* cell,
                               std::size_t cells) noexcept {
    std::uint8_t* const px = img.px;
    const std::ptrdiff_t s = img.stride;
    // (The pointers copied: a byte store could change them through a reference.)
    auto copy_back = [px, cell, s, cells](std::ptrdiff_t first, std::ptrdiff_t end) {
      if (static_cast<std::size_t>(end + 2 * s) < cells)
        for (std::ptrdiff_t i = first + 2 * s; i < end + 2 * s; i += 32) detail::prefetch(cell + i);
      for (std::ptrdiff_t i = first; i < end; ++i) px[i] = static_cast<std::uint8_t>(cell[i] & 1u);
    };
    if (img.loaded) {
      detail::for_each_run(img, copy_back);
      return;
    }
    for (int y = 0; y < img.height; ++y) {
      const std::ptrdiff_t row = img.index(0, y);
      int x = 0;
      for (const row_run r : img.runs->row(y)) {
        std::memset(px + row + x, 0, static_cast<std::size_t>(r.begin - x));
        copy_back(row + r.begin, row + r.end);
        x = r.end;
      }
      std::memset(px + row + x, 0, static_cast<std::size_t>(img.width - x));
    }
  }

  /// The queue laid out by `peel`: per key, the slice start[k] … fill[k] of `order` (fill
  /// grows as pixels are pushed), and the ring; the border pixels are in ring[0 … border).
  struct slices {
    std::uint32_t* fill;
    const std::uint32_t* start;
    std::uint32_t* order;
    std::uint32_t* ring;
    std::size_t ring_size;
    std::uint32_t top_key;
  };

  /// Queues the border pixels, then pops pixels by key until the queue is empty: a pixel is
  /// deleted when simple and not an end pixel, and its neighbours left are queued.
  template <class Pixels>
  static void drain(Pixels pixels, const detail::padded_image& img, const slices& q,
                    std::size_t border) noexcept {
    std::uint32_t* fill = q.fill;
    std::uint32_t* order = q.order;
    std::uint32_t* ring = q.ring;
    const std::size_t ring_size = q.ring_size;
    for (std::size_t b = 0; b < border; ++b) {
      const std::uint32_t i = ring[b];
      pixels.mark(static_cast<std::ptrdiff_t>(i));
      order[fill[pixels.key(static_cast<std::ptrdiff_t>(i))]++] = i;
    }
    std::ptrdiff_t offset[8];
    for (int k = 0; k < 8; ++k) offset[k] = img.offset[k];
    std::size_t ring_head = 0;
    std::size_t ring_tail = 0;
    std::uint32_t current = 0;
    // Pops pixel i: deletes it when simple and not an end pixel, queueing its neighbours left.
    auto visit = [&](std::uint32_t i) {
      const unsigned pairs = pixels.pairs(i);  // bits 2k, 2k + 1: neighbour k, and queued
      const unsigned c = detail::even_bits(pairs);
      if (!detail::deletable_table[c]) {
        pixels.keep(i);
        return;
      }
      pixels.erase(i);
      // The neighbours left (the bits of the code), in code order, unless already queued.
      for (unsigned fresh = pairs & ~(pairs >> 1) & 0x5555u; fresh != 0; fresh &= fresh - 1) {
        const std::ptrdiff_t n =
            static_cast<std::ptrdiff_t>(i) + offset[std::countr_zero(fresh) / 2];
        pixels.mark(n);
        const std::uint32_t k = pixels.key(n);
        if (k > current) {
          order[fill[k]++] = static_cast<std::uint32_t>(n);
        } else {
          ring[ring_tail] = static_cast<std::uint32_t>(n);
          ring_tail = ring_tail + 1 == ring_size ? 0 : ring_tail + 1;
        }
      }
    };
    constexpr std::uint32_t ahead = 8;  // pixels fetched ahead (a hint only; no effect)
    for (; current <= q.top_key; ++current) {
      const std::uint32_t end = fill[current];  // no more pixels join this slice
      for (std::uint32_t at = q.start[current]; at < end; ++at) {
        // (The prefetches stay here: GCC drops a call to a function that only prefetches.)
        if (at + ahead < end)
          for (const void* line : pixels.lines(order[at + ahead])) detail::prefetch(line);
        visit(order[at]);
      }
      while (ring_head != ring_tail) {
        const std::uint32_t i = ring[ring_head];
        ring_head = ring_head + 1 == ring_size ? 0 : ring_head + 1;
        visit(i);
      }
    }
  }
};

}  // namespace perch
