// SPDX-License-Identifier: BSL-1.0
/// \file
/// Pixel kinds of a one-pixel-thin skeleton (paper table 1, refined): end, body, junction,
/// isolated, from the 8-neighbourhood of each pixel, and the path adjacency that branch tracing
/// follows.
#pragma once

#include <array>
#include <bit>
#include <cstdint>

#include "perch/core/geometry.hpp"
#include "perch/core/image_view.hpp"
#include "perch/core/result.hpp"
#include "perch/core/row_scan.hpp"

namespace perch {

/// What a skeleton pixel is, from its 8-neighbourhood.
enum class pixel_kind : std::uint8_t {
  background,  ///< not a skeleton pixel
  isolated,    ///< no skeleton neighbour
  end,         ///< a branch tip: crossing number 1
  body,        ///< inside a branch: crossing number 2
  junction,    ///< where branches meet: crossing number ≥ 3, or part of a 2×2 block
};

/// Which of the 8 neighbours (bit i = `neighbours8[i]`: E, NE, N, NW, W, SW, S, SE) of
/// (`x`, `y`) are non-zero in `skeleton`; pixels outside the view count as zero.
/// Precondition: (`x`, `y`) inside the view. O(1).
template <BinaryView Skeleton>
[[nodiscard]] constexpr std::uint8_t neighbour_mask(const Skeleton& skeleton, int x,
                                                    int y) noexcept {
  if (x > 0 && y > 0 && x + 1 < skeleton.width() && y + 1 < skeleton.height()) {
    // Inside: three rows read directly, in `neighbours8` order, with no bounds test.
    const auto* above = detail::row_pointer(skeleton, y - 1) + x;
    const auto* here = detail::row_pointer(skeleton, y) + x;
    const auto* below = detail::row_pointer(skeleton, y + 1) + x;
    auto bit = [](auto v, int i) { return static_cast<unsigned>(static_cast<bool>(v)) << i; };
    return static_cast<std::uint8_t>(bit(here[1], 0) | bit(above[1], 1) | bit(above[0], 2) |
                                     bit(above[-1], 3) | bit(here[-1], 4) | bit(below[-1], 5) |
                                     bit(below[0], 6) | bit(below[1], 7));
  }
  unsigned mask = 0;
  for (int i = 0; i < 8; ++i) {
    const int nx = x + neighbours8[i].x;
    const int ny = y + neighbours8[i].y;
    if (skeleton.contains(nx, ny) && static_cast<bool>(skeleton(nx, ny))) mask |= 1u << i;
  }
  return static_cast<std::uint8_t>(mask);
}

/// The crossing number of a neighbourhood: the number of 0 → 1 transitions met walking once
/// around the 8 neighbours (Rutovitz's count; 0 for an empty or full ring). On a thin skeleton
/// it is the number of separate strokes that leave the pixel: 1 at an end, 2 on a body pixel
/// (also at the corner of a staircase, where the 8-neighbour count is 3 or 4), ≥ 3 at a
/// junction. O(1).
[[nodiscard]] constexpr int crossing_number(std::uint8_t neighbours) noexcept {
  int count = 0;
  for (int i = 0; i < 8; ++i) {
    const bool here = (static_cast<unsigned>(neighbours) >> i) & 1u;
    const bool next = (static_cast<unsigned>(neighbours) >> ((i + 1) % 8)) & 1u;
    count += (!here && next) ? 1 : 0;
  }
  return count;
}

/// True when the pixel is one of the four pixels of a 2×2 block of skeleton pixels (two 4-
/// neighbours and the diagonal between them are set). A thin skeleton has none; where a
/// skeleton has one, its pixels are junction pixels, so the block becomes one junction cluster.
[[nodiscard]] constexpr bool in_block(std::uint8_t neighbours) noexcept {
  for (int i = 1; i < 8; i += 2) {
    const unsigned corner = (1u << (i - 1)) | (1u << i) | (1u << ((i + 1) % 8));
    if ((neighbours & corner) == corner) return true;
  }
  return false;
}

/// The path neighbours of a pixel: its 4-neighbours, and each diagonal neighbour that is not
/// also reachable through a set 4-neighbour (the "m-adjacency" of digital topology). Walking a
/// thin skeleton along path neighbours never jumps a staircase corner and never steps across
/// a junction diagonally; the count of path neighbours equals the crossing number for every
/// neighbourhood that is not part of a 2×2 block. O(1).
[[nodiscard]] constexpr std::uint8_t path_neighbours(std::uint8_t neighbours) noexcept {
  std::uint8_t out = static_cast<std::uint8_t>(neighbours & 0x55u);  // E, N, W, S
  for (int i = 1; i < 8; i += 2) {
    const unsigned sides = (1u << (i - 1)) | (1u << ((i + 1) % 8));
    if (((static_cast<unsigned>(neighbours) >> i) & 1u) && (neighbours & sides) == 0)
      out = static_cast<std::uint8_t>(out | (1u << i));
  }
  return out;
}

/// The kind of a skeleton pixel with the given 8-neighbourhood (see `pixel_kind`):
/// no neighbour → isolated; in a 2×2 block → junction; otherwise by crossing number
/// (1 end, 2 body, ≥ 3 junction). So a T, Y, X or + centre is a junction, the corners of a
/// staircase (4-connected diagonal) are body pixels, and a one-pixel stub off a line is an end.
[[nodiscard]] constexpr pixel_kind classify_neighbourhood(std::uint8_t neighbours) noexcept {
  if (neighbours == 0) return pixel_kind::isolated;
  if (in_block(neighbours)) return pixel_kind::junction;
  const int c = crossing_number(neighbours);
  if (c <= 1) return pixel_kind::end;
  return c == 2 ? pixel_kind::body : pixel_kind::junction;
}

namespace detail {
/// `classify_neighbourhood` and `path_neighbours` for all 256 neighbourhoods.
struct pixel_kind_table {
  std::array<pixel_kind, 256> kind{};
  std::array<std::uint8_t, 256> path{};
};
[[nodiscard]] constexpr pixel_kind_table make_pixel_kind_table() noexcept {
  pixel_kind_table t;
  for (unsigned m = 0; m < 256; ++m) {
    const auto mask = static_cast<std::uint8_t>(m);
    t.kind[m] = classify_neighbourhood(mask);
    t.path[m] = path_neighbours(mask);
  }
  return t;
}
inline constexpr pixel_kind_table pixel_kinds_by_mask = make_pixel_kind_table();
}  // namespace detail

/// The kind of pixel (`x`, `y`) of `skeleton` (background if it is zero). Precondition: the
/// pixel lies inside the view. O(1).
template <BinaryView Skeleton>
[[nodiscard]] constexpr pixel_kind skeleton_pixel_kind(const Skeleton& skeleton, int x,
                                                       int y) noexcept {
  if (!static_cast<bool>(skeleton(x, y))) return pixel_kind::background;
  return detail::pixel_kinds_by_mask.kind[neighbour_mask(skeleton, x, y)];
}

/// Writes the kind of every pixel of `skeleton` to `kinds`.
///
/// Preconditions: `skeleton` is one pixel thin and 8-connected (any input is classified, but
/// thick blobs become junctions). Errors: view errors of either view, `size_mismatch`.
/// Complexity: O(width × height). Implements table 1 of the paper with the crossing-number
/// refinement described at `classify_neighbourhood`.
template <BinaryView Skeleton>
[[nodiscard]] status classify_skeleton(const Skeleton& skeleton,
                                       image_view<pixel_kind> kinds) noexcept {
  PERCH_TRY(validate(skeleton));
  PERCH_TRY(validate(kinds));
  PERCH_TRY(same_size(skeleton, kinds));
  for (int y = 0; y < skeleton.height(); ++y)
    for (int x = 0; x < skeleton.width(); ++x) kinds(x, y) = skeleton_pixel_kind(skeleton, x, y);
  return {};
}

}  // namespace perch
