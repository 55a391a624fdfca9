// SPDX-License-Identifier: BSL-1.0
/// \file
/// Classic two-sub-iteration parallel thinning: one template, `two_subiteration_thinning`,
/// parameterised by the deletion rule, and its two instances Zhang–Suen (1984) and Guo–Hall
/// (1989), exactly as their papers define them, computed by processing only the pixels that can
/// still change.
#pragma once

#include <bit>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string_view>

#include "perch/core/image_view.hpp"
#include "perch/core/prefetch.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/workspace.hpp"
#include "perch/skeleton/detail/topology.hpp"
#include "perch/skeleton/skeletoniser.hpp"

namespace perch {
namespace detail {

/// The eight neighbours of the pixel at `p` as a gathered code: bit 0 NW, 1 SW, 2 W, 3 N, 4 S,
/// 5 NE, 6 SE, 7 E. Three byte-row loads and one multiply instead of eight byte loads (the
/// multiply moves the three columns' bits to bits 24–31 without carries); the same code, byte
/// by byte, on a big-endian machine. Reads [p − stride − 1, p + stride + 1] only.
[[nodiscard]] inline unsigned gathered_code(const std::uint8_t* p, std::ptrdiff_t stride) noexcept {
  if constexpr (std::endian::native == std::endian::little) {
    std::uint32_t top = 0, middle = 0, bottom = 0;
    std::memcpy(&top, p - stride - 1, 4);     // NW N NE
    std::memcpy(&middle, p - 1, 4);           // W p E
    std::memcpy(&bottom, p + stride - 2, 4);  // SW S SE in bytes 1–3
    const std::uint32_t v = (top & 0x010101u) | (middle & 0x010001u) << 2 |
                            ((bottom >> 8) & 0x010101u) << 1;
    return (v * 0x01082000u) >> 24;
  } else {
    const std::ptrdiff_t s = stride;
    return (p[-s - 1] & 1u) | (p[s - 1] & 1u) << 1 | (p[-1] & 1u) << 2 | (p[-s] & 1u) << 3 |
           (p[s] & 1u) << 4 | (p[-s + 1] & 1u) << 5 | (p[s + 1] & 1u) << 6 | (p[1] & 1u) << 7;
  }
}

/// `table` re-indexed by `gathered_code`.
[[nodiscard]] constexpr neighbourhood_table gathered_table(
    const neighbourhood_table& table) noexcept {
  constexpr int code_bit[8] = {7, 5, 6, 0, 4, 1, 3, 2};  // code() bit of gathered bit k
  neighbourhood_table out{};
  for (unsigned g = 0; g < 256; ++g) {
    unsigned code = 0;
    for (int k = 0; k < 8; ++k) code |= ((g >> k) & 1u) << code_bit[k];
    out[g] = table[code];
  }
  return out;
}

/// Zhang–Suen's deletion rule as `two_subiteration_thinning` takes it: the method's name and
/// its two sub-iterations' deletion tables in neighbourhood-code order.
struct zhang_suen_rule {
  static constexpr std::string_view name = "zhang_suen";
  static constexpr neighbourhood_table tables[2] = {make_zhang_suen_table(0),
                                                    make_zhang_suen_table(1)};
};

/// Guo–Hall's deletion rule (algorithm A1) as `two_subiteration_thinning` takes it.
struct guo_hall_rule {
  static constexpr std::string_view name = "guo_hall";
  static constexpr neighbourhood_table tables[2] = {make_guo_hall_table(0), make_guo_hall_table(1)};
};

/// True when `table` deletes no pixel whose four 4-neighbours are all foreground (code bits 0,
/// 2, 4, 6): the thinning lists only pixels with a background 4-neighbour at the start.
[[nodiscard]] constexpr bool keeps_interior(const neighbourhood_table& table) noexcept {
  for (unsigned code = 0; code < 256; ++code)
    if ((code & 0x55u) == 0x55u && table[code]) return false;
  return true;
}

/// A deletion rule of a two-sub-iteration thinning: a name and two 256-entry deletion tables
/// indexed by the neighbourhood code (`padded_image::code`), one per sub-iteration; neither
/// table may delete an interior pixel (`keeps_interior`, checked at compile time).
template <class R>
concept ThinningRule = requires {
  { R::name } -> std::convertible_to<std::string_view>;
  { R::tables[0] } -> std::convertible_to<const neighbourhood_table&>;
  { R::tables[1] } -> std::convertible_to<const neighbourhood_table&>;
} && keeps_interior(R::tables[0]) && keeps_interior(R::tables[1]);

/// `Rule`'s tables re-indexed by `gathered_code`, built at compile time.
template <ThinningRule Rule>
inline constexpr neighbourhood_table gathered_tables[2] = {gathered_table(Rule::tables[0]),
                                                           gathered_table(Rule::tables[1])};

/// Bytes the queue-driven thinning takes at most.
[[nodiscard]] constexpr std::size_t thinning_workspace_bytes(int width, int height) noexcept {
  if (width <= 0 || height <= 0) return 0;
  const std::size_t n = padded_pixels(width, height);
  return workspace::footprint<std::uint8_t>(n) + 3 * workspace::footprint<std::uint32_t>(n + 16);
}

/// Two-sub-iteration parallel thinning with deletion tables `tables[0]`, `tables[1]`.
///
/// Each sub-iteration decides every pixel on the image as it was when the sub-iteration began
/// (parallel semantics), then deletes all the pixels it chose. Only pixels whose 3×3
/// neighbourhood changed since they were last decided by the same sub-iteration are decided
/// again (two candidate lists, one per sub-iteration, with a flag per pixel against
/// duplicates); at the start, the pixels with a background 4-neighbour (the tables delete no
/// other pixel: `keeps_interior`). The result equals the whole-image sweep of the paper. It stops
/// when both lists are empty: a full iteration would delete nothing.
inline status thin_two_subiterations(const neighbourhood_table* tables,
                                     image_view<const std::uint8_t> mask,
                                     image_view<const std::uint32_t> dist2,
                                     image_view<std::uint8_t> skeleton, workspace& ws,
                                     thinness thin, const row_runs* runs) noexcept {
  const auto entry = ws.mark();
  auto loaded = load_padded(mask, ws);
  PERCH_TRY(all_ok(loaded));
  padded_image img = *loaded;
  img.runs = runs;
  const std::size_t n = padded_pixels(img.width, img.height) + 16;
  auto a_memory = ws.allocate<std::uint32_t>(n);
  auto b_memory = ws.allocate<std::uint32_t>(n);
  auto d_memory = ws.allocate<std::uint32_t>(n);
  if (auto ok = all_ok(a_memory, b_memory, d_memory); !ok) {
    ws.rewind(entry);
    return unexpected{ok.error()};
  }
  std::uint32_t* list[2] = {a_memory->data(), b_memory->data()};
  std::size_t size[2] = {0, 0};
  std::uint32_t* deleted = d_memory->data();
  std::uint8_t* px = img.px;
  constexpr std::uint8_t flag[2] = {2u, 4u};

  for_each_foreground(img, [&](std::ptrdiff_t i) {
    if (!img.on_border(i)) return;
    px[i] |= 6u;
    list[0][size[0]++] = static_cast<std::uint32_t>(i);
    list[1][size[1]++] = static_cast<std::uint32_t>(i);
  });

  int sub = 0;
  while (size[0] + size[1] > 0) {
    const neighbourhood_table& table = tables[sub];
    const std::uint32_t* listed = list[sub];
    const std::size_t listed_count = size[sub];
    std::size_t count = 0;
    // Decides with loads only: a byte stored here would stall the next word loads over it.
    for (std::size_t k = 0; k < listed_count; ++k) {
      const std::uint32_t i = listed[k];
      if (k + 16 < listed_count) {
        const std::uint8_t* ahead = px + listed[k + 16];
        prefetch(ahead - img.stride);
        prefetch(ahead);
        prefetch(ahead + img.stride);
      }
      // Branch-free: whether a listed pixel goes is unpredictable.
      deleted[count] = i;
      count += (px[i] & 1u) & static_cast<unsigned>(table[gathered_code(px + i, img.stride)]);
    }
    for (std::size_t k = 0; k < listed_count; ++k)
      px[listed[k]] &= static_cast<std::uint8_t>(~flag[sub]);
    size[sub] = 0;
    for (std::size_t k = 0; k < count; ++k) px[deleted[k]] &= static_cast<std::uint8_t>(~1u);
    for (std::size_t k = 0; k < count; ++k) {
      for (int j = 0; j < 8; ++j) {
        const auto q = static_cast<std::uint32_t>(static_cast<std::ptrdiff_t>(deleted[k]) + img.offset[j]);
        const std::uint8_t v = px[q];
        if ((v & 1u) == 0) continue;
        if ((v & 2u) == 0) list[0][size[0]++] = q;
        if ((v & 4u) == 0) list[1][size[1]++] = q;
        px[q] = static_cast<std::uint8_t>(v | 6u);
      }
    }
    sub ^= 1;
  }

  if (thin == thinness::one_pixel) (void)remove_blocks(img, mask, dist2, deleted);
  store_skeleton(img, skeleton);
  ws.rewind(entry);
  return {};
}

}  // namespace detail

/// Two-sub-iteration parallel thinning with deletion rule `Rule` (models `Skeletoniser`):
/// `zhang_suen` and `guo_hall` are this template with their papers' rules.
///
/// Each sub-iteration deletes, in parallel, every pixel its table says to delete; repeat until
/// an iteration deletes nothing. Computed with the rule's tables re-indexed at compile time,
/// deciding only pixels whose neighbourhood changed (`detail::thin_two_subiterations`).
/// Guarantees: skeleton ⊆ mask; deterministic; faithful mode equals the whole-image sweep of
/// the rule bit for bit, and is a fixed point (thinning it again changes nothing). The default
/// `thinness::one_pixel` then removes 2×2 blocks with the topology-preserving clean-up.
/// Errors: view errors, `size_mismatch`, workspace errors (needs `workspace_bytes`).
/// Complexity: O(width × height) for the copies plus O(pixels deleted × 8) for the thinning
/// (work proportional to the shape, not iterations × image area).
template <detail::ThinningRule Rule>
struct two_subiteration_thinning {
  static constexpr std::string_view name = Rule::name;
  perch::thinness thinness = perch::thinness::one_pixel;  ///< one_pixel (default) or faithful

  [[nodiscard]] static constexpr std::size_t workspace_bytes(int width, int height) noexcept {
    return detail::thinning_workspace_bytes(width, height);
  }

  [[nodiscard]] status operator()(image_view<const std::uint8_t> mask,
                                  image_view<const std::uint32_t> dist2,
                                  image_view<std::uint8_t> skeleton, workspace& ws) const noexcept {
    return (*this)(mask, dist2, skeleton, ws, row_runs{});
  }
  /// With the row runs of `mask` (see `RowRunSkeletoniser`): the same skeleton, the first
  /// candidates and the clean-up's blocks found from the runs.
  [[nodiscard]] status operator()(image_view<const std::uint8_t> mask,
                                  image_view<const std::uint32_t> dist2,
                                  image_view<std::uint8_t> skeleton, workspace& ws,
                                  const row_runs& runs) const noexcept {
    PERCH_TRY(detail::validate_skeleton_views(mask, dist2, skeleton));
    return detail::thin_two_subiterations(detail::gathered_tables<Rule>, mask, dist2, skeleton,
                                          ws, thinness, detail::runs_of(&runs, mask));
  }
};

/// Zhang–Suen thinning (models `Skeletoniser`).
///
/// T. Y. Zhang and C. Y. Suen, "A fast parallel algorithm for thinning digital patterns",
/// Communications of the ACM 27(3), 1984. With P2 … P9 the neighbours clockwise from north,
/// B the number of foreground neighbours and A the number of 01 patterns in P2, P3, …, P9, P2,
/// sub-iteration 1 deletes (in parallel) every pixel with 2 ≤ B ≤ 6, A = 1, P2·P4·P6 = 0 and
/// P4·P6·P8 = 0 (south-east boundary and north-west corner points); sub-iteration 2 uses
/// P2·P4·P8 = 0 and P2·P6·P8 = 0; repeat until an iteration deletes nothing. Computed with
/// 256-entry tables built at compile time, deciding only pixels whose neighbourhood changed.
///
/// Guarantees: as `two_subiteration_thinning`. Known properties of the method, kept in
/// faithful mode: it erases 2×2 squares (a component can vanish) and leaves 2×2 blocks on
/// diagonal strokes; the default `thinness::one_pixel` removes the blocks with the
/// topology-preserving clean-up.
/// Errors, complexity: as `two_subiteration_thinning`.
using zhang_suen = two_subiteration_thinning<detail::zhang_suen_rule>;

/// Guo–Hall thinning, algorithm A1 (models `Skeletoniser`).
///
/// Z. Guo and R. W. Hall, "Parallel thinning with two-subiteration algorithms", Communications
/// of the ACM 32(3), 1989. With x1 … x8 the neighbours counter-clockwise from east, a pixel is
/// deleted (in parallel) iff C(p) = 1, 2 ≤ N(p) ≤ 3, and (x2 ∨ x3 ∨ ¬x8) ∧ x1 = 0 in odd
/// sub-iterations, (x6 ∨ x7 ∨ ¬x4) ∧ x5 = 0 in even ones, where
/// C(p) = Σ ¬x(2k−1) ∧ (x(2k) ∨ x(2k+1)) (8-connectivity number) and
/// N(p) = min(N1, N2) with N1 = Σ x(2k−1) ∨ x(2k), N2 = Σ x(2k) ∨ x(2k+1); repeat until an
/// iteration deletes nothing. Same queue-driven computation as `zhang_suen`.
///
/// Guarantees: as `two_subiteration_thinning`; the method preserves connectivity (a 2×2 square
/// keeps one pixel). OpenCV's `ximgproc::thinning(THINNING_GUOHALL)` runs the two
/// sub-iterations in the other order, so its output differs by a few pixels.
/// Errors, complexity: as `two_subiteration_thinning`.
using guo_hall = two_subiteration_thinning<detail::guo_hall_rule>;

}  // namespace perch
