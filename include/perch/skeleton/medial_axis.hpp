/// \file
/// The default skeleton: a one-pixel-thin, topology-preserving medial axis on the ridges of the
/// distance map, by distance-ordered homotopic thinning.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "perch/core/image_view.hpp"
#include "perch/core/result.hpp"
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
/// Errors: view errors of the three views, `size_mismatch`, `workspace_too_small` /
/// `out_of_memory` from the workspace (needs `workspace_bytes(width, height)`).
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

  [[nodiscard]] status operator()(image_view<const std::uint8_t> mask,
                                  image_view<const std::uint32_t> dist2,
                                  image_view<std::uint8_t> skeleton, workspace& ws) const noexcept {
    PERCH_TRY(detail::validate_skeleton_views(mask, dist2, skeleton));
    const auto entry = ws.mark();
    const status s = run(mask, dist2, skeleton, ws);
    ws.rewind(entry);
    return s;
  }

 private:
  static constexpr std::uint32_t empty = 0xFFFFFFFFu;

  [[nodiscard]] status run(image_view<const std::uint8_t> mask,
                           image_view<const std::uint32_t> dist2,
                           image_view<std::uint8_t> skeleton, workspace& ws) const noexcept {
    auto loaded = detail::load_padded(mask, ws);
    if (!loaded) return unexpected{loaded.error()};
    const detail::padded_image img = *loaded;
    const std::uint32_t cap = max_dist2(img.width, img.height);
    auto next_memory = ws.allocate<std::uint32_t>(detail::padded_pixels(img.width, img.height) + 16);
    auto head_memory = ws.allocate<std::uint32_t>(std::size_t{cap} + 1);
    auto tail_memory = ws.allocate<std::uint32_t>(std::size_t{cap} + 1);
    if (!next_memory) return unexpected{next_memory.error()};
    if (!head_memory) return unexpected{head_memory.error()};
    if (!tail_memory) return unexpected{tail_memory.error()};
    std::uint32_t* next = next_memory->data();
    std::uint32_t* head = head_memory->data();
    std::uint32_t* tail = tail_memory->data();
    std::uint8_t* px = img.px;

    // Buckets are made empty lazily, up to the largest key pushed so far.
    std::int64_t ready = -1;
    std::uint32_t top = 0;
    auto key_of = [&](std::ptrdiff_t i) {
      const pixel p = img.position(i);
      const std::uint32_t d = dist2(p.x, p.y);
      return d < cap ? d : cap;
    };
    auto push = [&](std::ptrdiff_t i, std::uint32_t key) {
      while (ready < static_cast<std::int64_t>(key)) head[++ready] = empty;
      const auto u = static_cast<std::uint32_t>(i);
      next[u] = empty;
      if (head[key] == empty) {
        head[key] = u;
      } else {
        next[tail[key]] = u;
      }
      tail[key] = u;
      if (key > top) top = key;
      px[i] |= 2u;
    };

    detail::for_each_foreground(img, [&](std::ptrdiff_t i) {
      if (img.on_border(i)) push(i, key_of(i));
    });

    for (std::uint32_t current = 0; current <= top && ready >= 0; ++current) {
      while (head[current] != empty) {
        const std::uint32_t i = head[current];
        head[current] = next[i];
        px[i] &= static_cast<std::uint8_t>(~2u);
        const unsigned c = img.code(i);
        if (!detail::deletable_table[c]) continue;
        px[i] = 0;
        for (int k = 0; k < 8; ++k) {
          const std::ptrdiff_t q = static_cast<std::ptrdiff_t>(i) + img.offset[k];
          if ((px[q] & 3u) != 1u) continue;
          const std::uint32_t key = key_of(q);
          push(q, key > current ? key : current);
        }
      }
    }

    if (thinness == perch::thinness::one_pixel) (void)detail::remove_blocks(img, mask, dist2, next);
    detail::store_skeleton(img, skeleton);
    return {};
  }
};

}  // namespace perch
