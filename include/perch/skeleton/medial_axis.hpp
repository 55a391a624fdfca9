/// \file
/// The default skeleton: a one-pixel-thin, topology-preserving medial axis on the ridges of the
/// distance map, by distance-ordered homotopic thinning.
#pragma once

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
/// block of skeleton pixels); every skeleton pixel is an end pixel or not simple, so
/// skeletonising the skeleton gives it back (idempotent); deterministic (ties: distance, then
/// queue order). `dist2` only orders the peeling: any map gives a thin, topology-preserving
/// result; values above the largest distance the image can hold are clamped.
/// Errors: view errors of the three views, `size_mismatch`, `image_too_large` for a strip so
/// thin that its padded copy holds 2^31 pixels, `workspace_too_small` / `out_of_memory` from
/// the workspace (needs `workspace_bytes(width, height)`).
/// Complexity: O(width × height) for the copy in and out (byte sweeps) plus O(foreground) for
/// the peeling; no allocation beyond the workspace, which is given back on return.
struct medial_axis {
  static constexpr std::string_view name = "medial_axis";
  perch::thinness thinness = perch::thinness::one_pixel;  ///< one_pixel (default) or faithful

  /// The largest squared distance a `width` × `height` image can hold: ((min + 1) / 2)².
  [[nodiscard]] static constexpr std::uint32_t max_dist2(int width, int height) noexcept {
    const auto m = static_cast<std::uint32_t>((width < height ? width : height) + 1) / 2;
    return m * m;
  }

  /// Bytes of workspace a call takes at most (the padded working copy, the queue links and
  /// the buckets).
  [[nodiscard]] static constexpr std::size_t workspace_bytes(int width, int height) noexcept {
    if (width <= 0 || height <= 0) return 0;
    const std::size_t n = detail::padded_pixels(width, height);
    return workspace::footprint<std::uint8_t>(n) + workspace::footprint<std::uint32_t>(n + 16) +
           2 * workspace::footprint<std::uint32_t>(std::size_t{max_dist2(width, height)} + 1);
  }

  /// (`listed`: internal, see `detail::mask_runs`.)
  [[nodiscard]] status operator()(image_view<const std::uint8_t> mask,
                                  image_view<const std::uint32_t> dist2,
                                  image_view<std::uint8_t> skeleton, workspace& ws,
                                  detail::mask_runs listed = {}) const noexcept {
    PERCH_TRY(detail::validate_skeleton_views(mask, dist2, skeleton));
    const auto entry = ws.mark();
    const status s = run(mask, dist2, skeleton, ws, detail::runs_of(listed, mask));
    ws.rewind(entry);
    return s;
  }

 private:
  static constexpr std::uint32_t empty = 0x7FFFFFFFu;     ///< no pixel (end of a list)
  static constexpr std::uint32_t unqueued = 0x80000000u;  ///< see `peel`

  [[nodiscard]] status run(image_view<const std::uint8_t> mask,
                           image_view<const std::uint32_t> dist2,
                           image_view<std::uint8_t> skeleton, workspace& ws,
                           const row_runs* runs) const noexcept {
    // Fast path: a mask with a background frame (as `prepare_mask` makes) is thinned in the
    // output itself, and when `dist2` is laid out like the output its values are read by index.
    const bool in_place = detail::has_background_frame(mask) &&
                          skeleton.stride() <= static_cast<std::ptrdiff_t>(mask.width()) + 2;
    detail::padded_image img;
    if (in_place) {
      img = detail::load_in_place(mask, skeleton, runs);
    } else {
      auto loaded = detail::load_padded(mask, ws);
      if (!loaded) return unexpected{loaded.error()};
      img = *loaded;
    }
    img.runs = runs;
    const std::uint32_t cap = max_dist2(img.width, img.height);
    const std::size_t cells = in_place ? static_cast<std::size_t>(img.stride) *
                                             static_cast<std::size_t>(img.height)
                                       : detail::padded_pixels(img.width, img.height);
    // Pixel indices must stay below `empty` (only a degenerate strip, e.g. 1 × 2^30, reaches it).
    if (cells >= empty) return fail(errc::image_too_large, "medial_axis: too many pixels");
    auto next_memory = ws.allocate<std::uint32_t>(cells + 16);
    if (!next_memory) return unexpected{next_memory.error()};
    std::uint32_t* next = next_memory->data();
    const status peeled = in_place && dist2.stride() == img.stride
                              ? peel(img, next, ws, cap, distances_by_index{dist2.data()})
                              : peel(img, next, ws, cap, distances_by_position{&img, dist2});
    if (!peeled) return peeled;
    if (thinness == perch::thinness::one_pixel)
      (void)detail::remove_blocks(img, mask, dist2, next);
    if (!in_place) detail::store_skeleton(img, skeleton);
    return {};
  }

  /// Where the distances of a run of the working image starting at pixel `i` are: at the same
  /// index when `dist2` is laid out like the working image, else found from the run's position
  /// (a run lies in one row of both images).
  struct distances_by_index {
    const std::uint32_t* d;
    const std::uint32_t* run(std::ptrdiff_t i) const noexcept { return d + i; }
  };
  struct distances_by_position {
    const detail::padded_image* img;
    image_view<const std::uint32_t> dist2;
    const std::uint32_t* run(std::ptrdiff_t i) const noexcept {
      const pixel p = img->position(i);
      return &dist2(p.x, p.y);
    }
  };

  /// The monotone bucket queue: FIFO lists per key, linked through `next`, heads and tails
  /// per key up to the largest key present.
  struct buckets {
    std::uint32_t* next;
    std::uint32_t* head;
    std::uint32_t* tail;

    void push(std::uint32_t u, std::uint32_t key) noexcept {
      next[u] = empty;
      if (head[key] == empty) {
        head[key] = u;
      } else {
        next[tail[key]] = u;
      }
      tail[key] = u;
    }
  };

  /// `next` doubles as the key store: a pixel out of the queue holds `unqueued` + its key there
  /// (filled in one raster pass, so the peeling never reads `dist2`), a queued one its link
  /// (below `unqueued`: pixel indices are below `empty`, keys below 2^31), and a popped pixel kept
  /// `unqueued` + the bucket it left, which is at least its key and at most any later bucket,
  /// so it re-enters at the current one as with its key. The same pass queues the border pixels
  /// (in raster order); the buckets have room for every key up to `cap` and are made empty up
  /// to the largest key seen so far.
  template <class Distances>
  [[nodiscard]] static status peel(const detail::padded_image& img, std::uint32_t* next,
                                   workspace& ws, std::uint32_t cap, Distances distances) noexcept {
    std::uint8_t* px = img.px;
    auto head_memory = ws.allocate<std::uint32_t>(std::size_t{cap} + 1);
    auto tail_memory = ws.allocate<std::uint32_t>(std::size_t{cap} + 1);
    if (!head_memory) return unexpected{head_memory.error()};
    if (!tail_memory) return unexpected{tail_memory.error()};
    buckets q{next, head_memory->data(), tail_memory->data()};
    std::uint32_t top_key = 0;
    q.head[0] = empty;
    detail::for_each_run(img, [&](std::ptrdiff_t first, std::ptrdiff_t end) {
      // The key: dist2, clamped to `cap`.
      const std::uint32_t* d = distances.run(first);
      std::uint32_t run_top = top_key;
      for (std::ptrdiff_t i = first; i < end; ++i) {
        const std::uint32_t key = d[i - first] < cap ? d[i - first] : cap;
        run_top = key > run_top ? key : run_top;
        next[i] = unqueued + key;
      }
      while (top_key < run_top) q.head[++top_key] = empty;
      // The border pixels in raster order: the run's two ends, and between them the pixels
      // below or above background, found eight at a time.
      auto push = [&](std::ptrdiff_t i) {
        q.push(static_cast<std::uint32_t>(i), next[i] - unqueued);
      };
      push(first);
      const std::ptrdiff_t last = end - 1;
      std::ptrdiff_t i = first + 1;
      for (; i + 8 <= last; i += 8) {
        std::uint64_t up = 0, down = 0;
        std::memcpy(&up, px + i - img.stride, 8);
        std::memcpy(&down, px + i + img.stride, 8);
        detail::for_each_set_byte(~(up & down) & 0x0101010101010101ull,
                                  [&](int k) { push(i + k); });
      }
      for (; i < last; ++i)
        if ((px[i - img.stride] & px[i + img.stride]) == 0) push(i);
      if (last > first) push(last);
    });

    std::ptrdiff_t offset[8];
    for (int k = 0; k < 8; ++k) offset[k] = img.offset[k];
    for (std::uint32_t current = 0; current <= top_key; ++current) {
      while (q.head[current] != empty) {
        const std::uint32_t i = q.head[current];
        const std::uint32_t after = next[i];
        q.head[current] = after;
        if (after != empty && next[after] != empty) {
          // The pixels of a level lie all over the image: fetch the neighbourhood of the one
          // after next while this one is worked on (a hint only; no effect on the result).
          const std::uint32_t ahead = next[after];
          detail::prefetch(px + ahead - img.stride);
          detail::prefetch(px + ahead);
          detail::prefetch(px + ahead + img.stride);
          detail::prefetch(next + ahead - img.stride);
          detail::prefetch(next + ahead);
          detail::prefetch(next + ahead + img.stride);
        }
        const unsigned c = img.code_of_bits(i);  // the peel sets no flags
        if (!detail::deletable_table[c]) {
          next[i] = unqueued + current;
          continue;
        }
        px[i] = 0;
        // The neighbours left (the bits of the code), in code order, unless already queued.
        for (unsigned left = c; left != 0; left &= left - 1) {
          const std::ptrdiff_t n = static_cast<std::ptrdiff_t>(i) + offset[std::countr_zero(left)];
          if (next[n] < unqueued) continue;
          const std::uint32_t key = next[n] - unqueued;
          q.push(static_cast<std::uint32_t>(n), key > current ? key : current);
        }
      }
    }
    return {};
  }
};

}  // namespace perch
