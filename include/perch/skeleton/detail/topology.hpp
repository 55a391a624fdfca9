// SPDX-License-Identifier: BSL-1.0
/// \file
/// Private helpers of the skeleton stage: a padded working copy of the mask (one byte per pixel,
/// background frame, bit 0 = foreground, bits 1–2 = queue flags), 3×3 neighbourhood codes,
/// compile-time 256-entry lookup tables (simple pixels; Zhang–Suen and Guo–Hall deletion
/// rules), the one-pixel clean-up, and the output copy.
///
/// Neighbourhood code: bit k is the k-th neighbour clockwise from north:
///   bit 7 NW | bit 0 N | bit 1 NE
///   bit 6 W  |    p    | bit 2 E
///   bit 5 SW | bit 4 S | bit 3 SE
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>

#include "perch/core/geometry.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/prefetch.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_runs.hpp"
#include "perch/core/row_scan.hpp"
#include "perch/core/workspace.hpp"

namespace perch::detail {

using neighbourhood_table = std::array<bool, 256>;

/// (dx, dy) of code bit k.
inline constexpr int code_dx[8] = {0, 1, 1, 1, 0, -1, -1, -1};
inline constexpr int code_dy[8] = {-1, -1, 0, 1, 1, 1, 0, -1};

[[nodiscard]] constexpr bool bit(unsigned code, int k) noexcept { return ((code >> k) & 1u) != 0; }

/// Bits 0, 2, …, 14 of `pairs` packed into bits 0…7.
[[nodiscard]] constexpr unsigned even_bits(unsigned pairs) noexcept {
  unsigned x = pairs & 0x5555u;
  x = (x | x >> 1) & 0x3333u;
  x = (x | x >> 2) & 0x0F0Fu;
  return (x | x >> 4) & 0x00FFu;
}

/// Rosenfeld's simple pixel: deleting p keeps the 8-components of the foreground and the
/// 4-components of the background. Locally: the foreground of N8(p) forms exactly one
/// 8-component, and the background of N8(p) has exactly one 4-component that is 4-adjacent to
/// p. Built by counting components in the 3×3 window (not from a formula), so the table is
/// checkable against the Yokoi connectivity number in the tests.
[[nodiscard]] constexpr neighbourhood_table make_simple_table() noexcept {
  neighbourhood_table table{};
  for (unsigned code = 0; code < 256; ++code) {
    auto count = [code](bool foreground) {
      int label[8] = {-1, -1, -1, -1, -1, -1, -1, -1};
      int components = 0;
      int touching_p = 0;
      for (int start = 0; start < 8; ++start) {
        if (bit(code, start) != foreground || label[start] >= 0) continue;
        int stack[8] = {};
        int top = 0;
        stack[top++] = start;
        label[start] = components;
        bool four_adjacent_to_p = false;
        while (top > 0) {
          const int k = stack[--top];
          if (code_dx[k] == 0 || code_dy[k] == 0) four_adjacent_to_p = true;
          for (int j = 0; j < 8; ++j) {
            if (bit(code, j) != foreground || label[j] >= 0) continue;
            const int ax = code_dx[j] - code_dx[k];
            const int ay = code_dy[j] - code_dy[k];
            const int dist = (ax < 0 ? -ax : ax) + (ay < 0 ? -ay : ay);
            const bool adjacent = foreground ? (ax >= -1 && ax <= 1 && ay >= -1 && ay <= 1)
                                             : dist == 1;
            if (!adjacent) continue;
            label[j] = components;
            stack[top++] = j;
          }
        }
        ++components;
        if (four_adjacent_to_p) ++touching_p;
      }
      return foreground ? components : touching_p;
    };
    table[code] = count(true) == 1 && count(false) == 1;
  }
  return table;
}

inline constexpr neighbourhood_table simple_table = make_simple_table();

/// Simple and not an end pixel (at least two foreground neighbours): what the medial axis and
/// the clean-up may delete. One table lookup (no popcount instruction needed).
[[nodiscard]] constexpr neighbourhood_table make_deletable_table() noexcept {
  neighbourhood_table table{};
  for (unsigned code = 0; code < 256; ++code)
    table[code] = simple_table[code] && std::popcount(code) >= 2;
  return table;
}
inline constexpr neighbourhood_table deletable_table = make_deletable_table();

/// Zhang & Suen 1984, with their names P2 = N, P3 = NE, …, P9 = NW (bits 0…7):
/// delete in sub-iteration 1 iff (a) 2 ≤ B ≤ 6, (b) A = 1, (c) P2·P4·P6 = 0, (d) P4·P6·P8 = 0;
/// in sub-iteration 2 with (c') P2·P4·P8 = 0 and (d') P2·P6·P8 = 0. B = number of foreground
/// neighbours; A = number of 01 patterns in the ordered sequence P2, P3, …, P9, P2.
[[nodiscard]] constexpr neighbourhood_table make_zhang_suen_table(int sub_iteration) noexcept {
  neighbourhood_table table{};
  for (unsigned code = 0; code < 256; ++code) {
    const int b = std::popcount(code);
    int a = 0;
    for (int k = 0; k < 8; ++k) a += !bit(code, k) && bit(code, (k + 1) % 8) ? 1 : 0;
    const bool p2 = bit(code, 0), p4 = bit(code, 2), p6 = bit(code, 4), p8 = bit(code, 6);
    const bool cd = sub_iteration == 0 ? !(p2 && p4 && p6) && !(p4 && p6 && p8)
                                       : !(p2 && p4 && p8) && !(p2 && p6 && p8);
    table[code] = b >= 2 && b <= 6 && a == 1 && cd;
  }
  return table;
}

/// Guo & Hall 1989, algorithm A1, with their names x1 = E, x2 = NE, x3 = N, x4 = NW, x5 = W,
/// x6 = SW, x7 = S, x8 = SE (counter-clockwise from east): delete iff (a) C(p) = 1,
/// (b) 2 ≤ N(p) ≤ 3, (c) (x2 ∨ x3 ∨ ¬x8) ∧ x1 = 0 in odd sub-iterations and
/// (x6 ∨ x7 ∨ ¬x4) ∧ x5 = 0 in even ones, where
/// C(p) = ¬x1∧(x2∨x3) + ¬x3∧(x4∨x5) + ¬x5∧(x6∨x7) + ¬x7∧(x8∨x1),
/// N(p) = min(N1, N2), N1 = (x1∨x2)+(x3∨x4)+(x5∨x6)+(x7∨x8), N2 = (x2∨x3)+(x4∨x5)+(x6∨x7)+(x8∨x1).
[[nodiscard]] constexpr neighbourhood_table make_guo_hall_table(int sub_iteration) noexcept {
  neighbourhood_table table{};
  for (unsigned code = 0; code < 256; ++code) {
    const bool x1 = bit(code, 2), x2 = bit(code, 1), x3 = bit(code, 0), x4 = bit(code, 7);
    const bool x5 = bit(code, 6), x6 = bit(code, 5), x7 = bit(code, 4), x8 = bit(code, 3);
    const int c = (!x1 && (x2 || x3)) + (!x3 && (x4 || x5)) + (!x5 && (x6 || x7)) +
                  (!x7 && (x8 || x1));
    const int n1 = (x1 || x2) + (x3 || x4) + (x5 || x6) + (x7 || x8);
    const int n2 = (x2 || x3) + (x4 || x5) + (x6 || x7) + (x8 || x1);
    const int n = n1 < n2 ? n1 : n2;
    const bool m = sub_iteration == 0 ? ((x2 || x3 || !x8) && x1) : ((x6 || x7 || !x4) && x5);
    table[code] = c == 1 && n >= 2 && n <= 3 && !m;
  }
  return table;
}

/// `padded_image::pairs` of the pixel at `p` in rows `stride` bytes apart.
[[nodiscard]] inline unsigned neighbour_pairs(const std::uint8_t* p,
                                              std::ptrdiff_t stride) noexcept {
  const std::ptrdiff_t s = stride;
  return static_cast<unsigned>(p[-s] | p[-s + 1] << 2 | p[1] << 4 | p[s + 1] << 6 | p[s] << 8 |
                               p[s - 1] << 10 | p[-1] << 12 | p[-s - 1] << 14);
}

/// The working image, one byte per pixel with a background frame: either a padded copy,
/// (width + 2) × (height + 2) bytes with pixel (x, y) at index (y + 1)·stride + x + 1
/// (`pad` = 1), or the caller's output itself when the mask's outermost rows and columns are
/// background, pixel (x, y) at index y·stride + x (`pad` = 0; the frame is the image's own
/// border, which stays background).
struct padded_image {
  std::uint8_t* px = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;
  std::ptrdiff_t offset[8] = {};  ///< index offsets of code bits 0…7
  double inv_stride = 0;
  int pad = 1;  ///< 1 for the padded copy, 0 when working in the output
  const row_runs* runs = nullptr;  ///< the runs of the mask it was loaded from, if known
  std::size_t pixels = 0;          ///< foreground pixels loaded
  /// False when the output was left unwritten (`load_in_place` with `load` false): the runs
  /// then stand for the mask, and the skeletoniser writes every pixel itself.
  bool loaded = true;

  [[nodiscard]] std::ptrdiff_t index(int x, int y) const noexcept {
    return (static_cast<std::ptrdiff_t>(y) + pad) * stride + x + pad;
  }
  /// (x, y) of index `i`.
  [[nodiscard]] pixel position(std::ptrdiff_t i) const noexcept {
    auto row = static_cast<std::ptrdiff_t>(static_cast<double>(i) * inv_stride);
    if (row * stride > i) --row;
    if ((row + 1) * stride <= i) ++row;
    return {static_cast<std::int32_t>(i - row * stride - pad), static_cast<std::int32_t>(row - pad)};
  }
  [[nodiscard]] unsigned code(std::ptrdiff_t i) const noexcept {
    const std::uint8_t* p = px + i;
    const std::ptrdiff_t s = stride;
    return (p[-s] & 1u) | (p[-s + 1] & 1u) << 1 | (p[1] & 1u) << 2 | (p[s + 1] & 1u) << 3 |
           (p[s] & 1u) << 4 | (p[s - 1] & 1u) << 5 | (p[-1] & 1u) << 6 | (p[-s - 1] & 1u) << 7;
  }
  /// The 8-neighbourhood of `i` with two bits per neighbour, in code order (neighbour k in bits
  /// 2k and 2k + 1), when every byte is 0, 1 or 3 (foreground and bit 1 as a flag): its
  /// `code` is `even_bits(pairs(i))`.
  [[nodiscard]] unsigned pairs(std::ptrdiff_t i) const noexcept {
    return neighbour_pairs(px + i, stride);
  }
  /// True when a 4-neighbour of `i` is background.
  [[nodiscard]] bool on_border(std::ptrdiff_t i) const noexcept {
    return ((px[i - stride] & px[i + stride] & px[i - 1] & px[i + 1]) & 1u) == 0;
  }
};

[[nodiscard]] constexpr std::size_t padded_pixels(int width, int height) noexcept {
  return (static_cast<std::size_t>(width) + 2) * (static_cast<std::size_t>(height) + 2);
}

/// Copies `mask` (non-zero = 1) into a padded image taken from `ws`.
[[nodiscard]] inline result<padded_image> load_padded(image_view<const std::uint8_t> mask,
                                                      workspace& ws) noexcept {
  padded_image img;
  img.width = mask.width();
  img.height = mask.height();
  img.stride = img.width + 2;
  img.inv_stride = 1.0 / static_cast<double>(img.stride);
  for (int k = 0; k < 8; ++k) img.offset[k] = code_dy[k] * img.stride + code_dx[k];
  auto memory = ws.allocate<std::uint8_t>(padded_pixels(img.width, img.height));
  PERCH_TRY(all_ok(memory));
  img.px = memory->data();
  std::memset(img.px, 0, static_cast<std::size_t>(img.stride));
  std::memset(img.px + (static_cast<std::ptrdiff_t>(img.height) + 1) * img.stride, 0,
              static_cast<std::size_t>(img.stride));
  for (int y = 0; y < img.height; ++y) {
    const std::uint8_t* m = mask.data() + static_cast<std::ptrdiff_t>(y) * mask.stride();
    std::uint8_t* d = img.px + img.index(0, y);
    d[-1] = 0;
    d[img.width] = 0;
    img.pixels += binarise_row(m, d, img.width);
  }
  return img;
}

/// True when every pixel of the outermost rows and columns of `mask` is background (and the
/// mask is at least 3 × 3), so the skeletonisers may work in their output directly.
[[nodiscard]] inline bool has_background_frame(image_view<const std::uint8_t> mask) noexcept {
  const int w = mask.width();
  const int h = mask.height();
  if (w < 3 || h < 3) return false;
  const std::uint8_t* first = mask.data();
  const std::uint8_t* last = mask.data() + static_cast<std::ptrdiff_t>(h - 1) * mask.stride();
  for (int x = 0; x < w; ++x)
    if ((first[x] | last[x]) != 0) return false;
  for (int y = 1; y + 1 < h; ++y) {
    const std::uint8_t* row = mask.data() + static_cast<std::ptrdiff_t>(y) * mask.stride();
    if ((row[0] | row[w - 1]) != 0) return false;
  }
  return true;
}

/// The working image in `out` itself (`pad` = 0), `mask` (non-zero = 1) copied into it (from
/// `runs` when given: they must describe `mask`); with runs and `load` false, nothing is
/// written (`loaded` false) and only the foreground is counted.
/// Precondition: `has_background_frame(mask)`, `out` of the same size.
[[nodiscard]] inline padded_image load_in_place(image_view<const std::uint8_t> mask,
                                                image_view<std::uint8_t> out,
                                                const row_runs* runs = nullptr,
                                                bool load = true) noexcept {
  padded_image img;
  img.width = mask.width();
  img.height = mask.height();
  img.stride = out.stride();
  img.pad = 0;
  img.inv_stride = 1.0 / static_cast<double>(img.stride);
  for (int k = 0; k < 8; ++k) img.offset[k] = code_dy[k] * img.stride + code_dx[k];
  img.px = out.data();
  if (runs != nullptr && !load) {
    img.loaded = false;
    for (int y = 0; y < img.height; ++y)
      for (const row_run r : runs->row(y)) img.pixels += static_cast<std::size_t>(r.end - r.begin);
    return img;
  }
  for (int y = 0; y < img.height; ++y) {
    const std::uint8_t* m = mask.data() + static_cast<std::ptrdiff_t>(y) * mask.stride();
    std::uint8_t* d = img.px + static_cast<std::ptrdiff_t>(y) * img.stride;
    if (runs == nullptr) {
      img.pixels += binarise_row(m, d, img.width);
      continue;
    }
    std::memset(d, 0, static_cast<std::size_t>(img.width));
    for (const row_run r : runs->row(y)) {
      std::memset(d + r.begin, 1, static_cast<std::size_t>(r.end - r.begin));
      img.pixels += static_cast<std::size_t>(r.end - r.begin);
    }
  }
  return img;
}

/// Writes bit 0 of the working image to `out` (1 skeleton, 0 not), every pixel.
inline void store_skeleton(const padded_image& img, image_view<std::uint8_t> out) noexcept {
  for (int y = 0; y < img.height; ++y) {
    const std::uint8_t* s = img.px + img.index(0, y);
    std::uint8_t* d = out.data() + static_cast<std::ptrdiff_t>(y) * out.stride();
    for (int x = 0; x < img.width; ++x) d[x] = s[x] & 1u;
  }
}

/// Calls `visit(first, end)` for every run [first, end) of foreground pixels in a row of the
/// working image, in raster order, skipping eight background bytes at a time. Precondition: no
/// flag is set yet (every byte is 0 or 1); `visit` may set flags on the run it is given.
template <class Visit>
inline void for_each_run(const padded_image& img, Visit&& visit) noexcept {
  for (int y = 0; y < img.height; ++y) {
    const std::ptrdiff_t row = img.index(0, y);
    for_each_run_in_row(img.runs, y, img.px + row, img.width,
                        [&](int a, int b) { visit(row + a, row + b); });
  }
}

/// Calls `visit(i)` for every foreground pixel of the working image, in raster order (as
/// `for_each_run`, same precondition).
template <class Visit>
inline void for_each_foreground(const padded_image& img, Visit&& visit) noexcept {
  for_each_run(img, [&](std::ptrdiff_t first, std::ptrdiff_t end) {
    for (std::ptrdiff_t i = first; i < end; ++i) visit(i);
  });
}

/// Deletes simple non-end pixels among the neighbours of the pixels in `seeds` (and of what it
/// deletes), until none is left: the local redundancy sweep after a clean-up change. The seeds
/// are flagged (bit 1) and distinct; `queue` has room for every pixel.
inline void sweep_redundant(const padded_image& img, std::uint32_t* queue, std::size_t count) noexcept {
  std::size_t head = 0;
  std::size_t tail = count;
  while (head != tail) {
    const std::uint32_t i = queue[head++];
    img.px[i] &= static_cast<std::uint8_t>(~2u);
    if ((img.px[i] & 1u) == 0) continue;
    const unsigned c = img.code(static_cast<std::ptrdiff_t>(i));
    if (!deletable_table[c]) continue;
    img.px[i] = 0;
    for (int k = 0; k < 8; ++k) {
      const auto q = static_cast<std::uint32_t>(static_cast<std::ptrdiff_t>(i) + img.offset[k]);
      if ((img.px[q] & 3u) == 1u) {
        img.px[q] |= 2u;
        queue[tail++] = q;
      }
    }
  }
}

/// The deeper re-route of the one-pixel clean-up, for a 2×2 block none of whose pixels is
/// simple and which no single added neighbour frees (a pixel whose four 4-neighbours are all
/// skeleton pixels, or a branch leaving a corner diagonally, on every corner of the block: the
/// two single steps of `remove_blocks` fail). It looks for the shortest sequence of at most
/// `max_steps` changes inside the 4×4 window around the block (the block and the ring of twelve
/// pixels about it), each a simple-pixel change when it is made: deleting a skeleton pixel
/// that is simple and not an end pixel, or adding a pixel of the mask that is simple once added;
/// a pixel changes at most once. A sequence is taken when it has deleted a pixel of the block
/// and no pixel it added (and kept) lies in a 2×2 block. Each step is a simple-pixel change, so
/// the sequence keeps the 8-components of the skeleton and the 4-components of its complement
/// (Rosenfeld, "Connectivity in digital pictures", J. ACM 17(1), 1970: deleting or adding a
/// simple pixel is a homotopy, so a sequence of them is one too; T. Y. Kong and A. Rosenfeld,
/// "Digital topology: introduction and survey", CVGIP 48(3), 1989); it removes the block
/// and creates none, so the clean-up still terminates. Typical sequence: where a branch runs
/// into a corner pixel p whose four 4-neighbours are skeleton pixels, add the mask pixel in the
/// crook of the branch, delete the branch's pixel next to p, then p.
struct block_reroute {
  static constexpr int max_steps = 3;

  const padded_image& img;
  image_view<const std::uint8_t> mask;
  std::ptrdiff_t block[4] = {};
  std::ptrdiff_t window[16] = {};
  std::ptrdiff_t changed[max_steps] = {};  ///< pixels changed so far, in order
  int steps = 0;

  /// For the block whose top-left pixel is `i` (which must not touch the working image's frame).
  block_reroute(const padded_image& image, image_view<const std::uint8_t> m,
                std::ptrdiff_t i) noexcept
      : img(image), mask(m) {
    const std::ptrdiff_t s = img.stride;
    block[0] = i;
    block[1] = i + 1;
    block[2] = i + s;
    block[3] = i + s + 1;
    int k = 0;
    for (int dy = -1; dy <= 2; ++dy)
      for (int dx = -1; dx <= 2; ++dx) window[k++] = i + dy * s + dx;
  }

  [[nodiscard]] bool on(std::ptrdiff_t i) const noexcept { return (img.px[i] & 1u) != 0; }
  [[nodiscard]] bool in_mask(std::ptrdiff_t i) const noexcept {
    const pixel p = img.position(i);
    return p.x >= 0 && p.y >= 0 && p.x < img.width && p.y < img.height && mask(p.x, p.y) != 0;
  }
  [[nodiscard]] bool in_block(std::ptrdiff_t q) const noexcept {
    const std::ptrdiff_t s = img.stride;
    auto is_block = [&](std::ptrdiff_t i) {
      return ((img.px[i] & img.px[i + 1] & img.px[i + s] & img.px[i + s + 1]) & 1u) != 0;
    };
    return is_block(q) || is_block(q - 1) || is_block(q - s) || is_block(q - s - 1);
  }
  [[nodiscard]] bool was_changed(std::ptrdiff_t q) const noexcept {
    for (int k = 0; k < steps; ++k)
      if (changed[k] == q) return true;
    return false;
  }
  /// The block is gone and no pixel added so far lies in a block.
  [[nodiscard]] bool done() const noexcept {
    if (on(block[0]) && on(block[1]) && on(block[2]) && on(block[3])) return false;
    for (int k = 0; k < steps; ++k)
      if (on(changed[k]) && in_block(changed[k])) return false;
    return true;
  }
  /// Depth-first over the sequences of at most `budget` more steps; leaves the image changed
  /// and returns true on success, else leaves it as it was.
  [[nodiscard]] bool search(int budget) noexcept {
    if (done()) return true;
    if (budget == 0) return false;
    for (const std::ptrdiff_t q : window) {
      if (was_changed(q)) continue;
      const bool was_on = on(q);
      // A pixel outside the mask stays background; a skeleton pixel is inside the mask, so
      // codes are only read inside the working image's frame.
      if (!was_on && !in_mask(q)) continue;
      const unsigned c = img.code(q);
      if (was_on ? !deletable_table[c] : !simple_table[c]) continue;
      img.px[q] = was_on ? 0 : 1;
      changed[steps++] = q;
      if (search(budget - 1)) return true;
      --steps;
      img.px[q] = was_on ? 1 : 0;
    }
    return false;
  }
  /// Iterative deepening: the shortest sequence found first.
  [[nodiscard]] bool run() noexcept {
    for (int budget = 1; budget <= max_steps; ++budget)
      if (search(budget)) return true;
    return false;
  }
};

/// The state of `remove_blocks`' passes, and its steps on one block.
struct block_cleanup {
  const padded_image& img;
  image_view<const std::uint8_t> mask;
  image_view<const std::uint32_t> dist2;
  std::uint32_t* queue;   ///< pixels next to a change, to sweep for redundancy
  std::size_t seeded = 0;
  std::size_t left = 0;   ///< blocks left in this pass
  bool changed = false;   ///< whether this pass removed a block
  bool deep = false;      ///< whether `block_reroute` may be tried

  [[nodiscard]] std::uint32_t d2(std::ptrdiff_t i) const noexcept {
    const pixel p = img.position(i);
    return dist2(p.x, p.y);
  }
  [[nodiscard]] bool is_block(std::ptrdiff_t i) const noexcept {
    const std::ptrdiff_t s = img.stride;
    return ((img.px[i] & img.px[i + 1] & img.px[i + s] & img.px[i + s + 1]) & 1u) != 0;
  }
  [[nodiscard]] bool in_mask(std::ptrdiff_t i) const noexcept {
    const pixel p = img.position(i);
    return p.x >= 0 && p.y >= 0 && p.x < img.width && p.y < img.height && mask(p.x, p.y) != 0;
  }
  [[nodiscard]] bool makes_block(std::ptrdiff_t q) const noexcept {
    const std::ptrdiff_t s = img.stride;
    return is_block(q) || is_block(q - 1) || is_block(q - s) || is_block(q - s - 1);
  }
  /// Queues skeleton pixel `i` for the redundancy sweep (once).
  void seed(std::ptrdiff_t i) noexcept {
    if ((img.px[i] & 3u) != 1u) return;
    img.px[i] |= 2u;
    queue[seeded++] = static_cast<std::uint32_t>(i);
  }
  void seed_around(std::ptrdiff_t i) noexcept {
    for (int j = 0; j < 8; ++j) seed(i + img.offset[j]);
  }

  /// First step on a block (its pixels ordered by dist2, then raster): deletes the first
  /// simple one.
  [[nodiscard]] bool delete_simple_pixel(const std::ptrdiff_t (&block)[4]) noexcept {
    for (const std::ptrdiff_t p : block) {
      if (!deletable_table[img.code(p)]) continue;
      img.px[p] = 0;
      seed_around(p);
      return true;
    }
    return false;
  }

  /// Second step on the block whose top-left pixel is `i`: re-routes one branch, adding a
  /// neighbour q of a block pixel p, outside the block and inside the mask, whose addition is
  /// simple and creates no block, and deleting p, simple now.
  [[nodiscard]] bool reroute_branch(std::ptrdiff_t i, const std::ptrdiff_t (&block)[4]) noexcept {
    const std::ptrdiff_t s = img.stride;
    for (const std::ptrdiff_t p : block) {
      // The 8-neighbours of p outside the block: its two 4-neighbours first.
      const int sx = (p == i || p == i + s) ? -1 : 1;
      const int sy = (p == i || p == i + 1) ? -1 : 1;
      const std::ptrdiff_t outside[5] = {p + sy * s, p + sx, p + sy * s + sx, p + sy * s - sx,
                                         p + sx - sy * s};
      for (const std::ptrdiff_t q : outside) {
        if ((img.px[q] & 1u) != 0 || !in_mask(q)) continue;
        img.px[q] = 1;
        const unsigned cp = img.code(p);
        if (simple_table[img.code(q)] && !makes_block(q) && deletable_table[cp]) {
          img.px[p] = 0;
          seed(q);
          for (int j = 0; j < 8; ++j) {
            seed(q + img.offset[j]);
            seed(p + img.offset[j]);
          }
          return true;
        }
        img.px[q] = 0;
      }
    }
    return false;
  }

  /// Third step (second phase only): a `block_reroute` sequence.
  [[nodiscard]] bool reroute_deeper(std::ptrdiff_t i) noexcept {
    block_reroute reroute(img, mask, i);
    if (!reroute.run()) return false;
    for (int k = 0; k < reroute.steps; ++k) {
      const std::ptrdiff_t q = reroute.changed[k];
      seed(q);
      seed_around(q);
    }
    return true;
  }

  /// Removes the block whose top-left pixel is `i`, or counts it as left.
  void unblock(std::ptrdiff_t i) noexcept {
    const std::ptrdiff_t s = img.stride;
    std::ptrdiff_t block[4] = {i, i + 1, i + s, i + s + 1};
    // Order by dist2, then raster (insertion sort of four).
    std::uint32_t key[4] = {d2(block[0]), d2(block[1]), d2(block[2]), d2(block[3])};
    for (int k = 1; k < 4; ++k)
      for (int j = k; j > 0 && key[j] < key[j - 1]; --j) {
        std::swap(key[j], key[j - 1]);
        std::swap(block[j], block[j - 1]);
      }
    const bool done =
        delete_simple_pixel(block) || reroute_branch(i, block) || (deep && reroute_deeper(i));
    if (!done) {
      ++left;
      return;
    }
    changed = true;
    if (seeded > 0) {
      sweep_redundant(img, queue, seeded);
      seeded = 0;
    }
  }

  /// Visits the block corners x in [from, to − 1) of the row starting at index `row` (reads
  /// bytes from … to − 1 of it and of the row below), skipping 64, then 8 positions at a time
  /// where no block starts.
  void scan(std::ptrdiff_t row, int from, int to) noexcept {
    const std::uint8_t* r0 = img.px + row;
    const std::uint8_t* r1 = r0 + img.stride;
    // Non-zero iff a block starts in [x0, x0 + 8·words) (reads x0 … x0 + 8·words of both rows).
    auto block_bits = [&](int x0, int words) {
      std::uint64_t any = 0;
      for (int k = 0; k < words; ++k) {
        std::uint64_t a = 0, b = 0, c = 0, d = 0;
        std::memcpy(&a, r0 + x0 + 8 * k, 8);
        std::memcpy(&b, r0 + x0 + 8 * k + 1, 8);
        std::memcpy(&c, r1 + x0 + 8 * k, 8);
        std::memcpy(&d, r1 + x0 + 8 * k + 1, 8);
        any |= a & b & c & d;
      }
      return any & 0x0101010101010101ull;
    };
    int x = from;
    while (x + 1 < to) {
      if (x + 65 <= to && block_bits(x, 8) == 0) {
        x += 64;
        continue;
      }
      if (x + 9 <= to && block_bits(x, 1) == 0) {
        x += 8;
        continue;
      }
      const std::ptrdiff_t i = row + x;
      ++x;
      if (is_block(i)) unblock(i);
    }
  }

  /// One pass over the image's block corners.
  void pass() noexcept {
    changed = false;
    left = 0;
    for (int y = 0; y + 1 < img.height; ++y) {
      const std::ptrdiff_t row = img.index(0, y);
      if (img.runs != nullptr) {
        for (const row_run r : img.runs->row(y))
          scan(row, static_cast<int>(r.begin), static_cast<int>(r.end));
      } else {
        scan(row, 0, img.width);
      }
    }
  }
};

/// The one-pixel clean-up: removes every 2×2 block of skeleton pixels it can without changing
/// the topology. In each block it deletes the simple pixel of smallest dist2 (ties: raster
/// order); when no block pixel is simple (four branches meeting diagonally), it re-routes one
/// branch: adds a neighbour q of a block pixel p, outside the block and inside the mask, whose
/// addition is simple and creates no block, then deletes p if it is simple now. When neither
/// step frees any block left, a second phase also tries `block_reroute` (a short sequence of
/// simple changes around the block) on each; a skeleton the first phase cleans up completely
/// is never touched by it. All steps are simple-pixel changes, so components and holes are
/// kept; each step removes at least one block and adds none, so it terminates. Pixels next to
/// every change are then swept for redundancy (simple non-end pixels are deleted), so the
/// result is again irreducible.
/// Returns the number of blocks left: 0 unless the mask is hardly wider than the skeleton
/// around a block (noise masks). Some masks have no thin subset with their topology at all:
/// four one-pixel holes diagonally round a 2×2 block, each closed by its four 4-neighbours
/// and nothing more, force those neighbours, and any pixel taken out of the block is then a
/// new hole. `queue` must have room for every pixel.
inline std::size_t remove_blocks(const padded_image& img, image_view<const std::uint8_t> mask,
                                 image_view<const std::uint32_t> dist2,
                                 std::uint32_t* queue) noexcept {
  block_cleanup cleanup{img, mask, dist2, queue};
  // A block's top row has two skeleton pixels side by side, so it lies inside a run of the mask
  // (the skeleton stays inside the mask): only the runs are scanned when they are listed.
  // The deeper re-route only once the single steps are done with every block, so a skeleton
  // they clean up completely is the same as without it.
  for (int phase = 0; phase < 2 && (phase == 0 || cleanup.left > 0); ++phase) {
    cleanup.deep = phase == 1;
    do cleanup.pass();
    while (cleanup.changed);
  }
  return cleanup.left;
}

/// Views checked the same way by every skeletoniser.
[[nodiscard]] inline status validate_skeleton_views(image_view<const std::uint8_t> mask,
                                                    image_view<const std::uint32_t> dist2,
                                                    image_view<std::uint8_t> skeleton) noexcept {
  PERCH_TRY(validate_non_empty(mask));
  PERCH_TRY(validate(dist2));
  PERCH_TRY(validate(skeleton));
  PERCH_TRY(same_size(mask, dist2));
  PERCH_TRY(same_size(mask, skeleton));
  return {};
}

}  // namespace perch::detail
