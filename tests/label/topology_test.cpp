// SPDX-License-Identifier: BSL-1.0
#include "perch/label/topology.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <utility>
#include <vector>

#include "allocation_counter.hpp"
#include "perch/core/image.hpp"
#include "support/ascii_art.hpp"

using perch::errc;
using perch::image;
using perch::image_view;
using perch::topology_counts;
using perch::workspace;
using perch::support::mask_from_ascii;

namespace {

// Reference: flood fills on a copy of the mask padded with one background pixel all round.
// Components = 8-connected foreground fills; holes = 4-connected background fills minus the one
// that contains the padding (the outside).
template <perch::ImageView Mask>
topology_counts reference_topology(const Mask& mask) {
  const int w = mask.width() + 2;
  const int h = mask.height() + 2;
  std::vector<int> value(static_cast<std::size_t>(w * h), 0);
  for (int y = 0; y < mask.height(); ++y)
    for (int x = 0; x < mask.width(); ++x)
      value[static_cast<std::size_t>((y + 1) * w + x + 1)] = static_cast<bool>(mask(x, y)) ? 1 : 0;
  std::vector<char> seen(value.size(), 0);
  auto fill = [&](int sx, int sy, int want, bool diagonal) {
    std::vector<std::pair<int, int>> stack{{sx, sy}};
    seen[static_cast<std::size_t>(sy * w + sx)] = 1;
    while (!stack.empty()) {
      const auto [x, y] = stack.back();
      stack.pop_back();
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          if ((dx == 0 && dy == 0) || (!diagonal && dx != 0 && dy != 0)) continue;
          const int nx = x + dx;
          const int ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const auto i = static_cast<std::size_t>(ny * w + nx);
          if (seen[i] == 0 && value[i] == want) {
            seen[i] = 1;
            stack.push_back({nx, ny});
          }
        }
    }
  };
  topology_counts out{0, 0};
  int background = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const auto i = static_cast<std::size_t>(y * w + x);
      if (seen[i] != 0) continue;
      if (value[i] == 1) {
        ++out.components;
        fill(x, y, 1, true);
      } else {
        ++background;
        fill(x, y, 0, false);
      }
    }
  out.holes = background - 1;  // the padding's region is the outside
  return out;
}

topology_counts topology_of(std::string_view art) {
  const auto mask = mask_from_ascii(art);
  workspace ws;
  auto counts = perch::count_topology(mask.view(), ws);
  REQUIRE(counts);
  CHECK(*counts == reference_topology(mask.view()));
  return *counts;
}

}  // namespace

TEST_CASE("count_topology: ASCII-art shapes") {
  CHECK(topology_of("#") == topology_counts{1, 0});
  CHECK(topology_of(".") == topology_counts{0, 0});
  CHECK(topology_of("###\n#.#\n###") == topology_counts{1, 1});
  // An 8-connected diamond: its inside is a 4-connected hole.
  CHECK(topology_of(R"(
    ..#..
    .#.#.
    #...#
    .#.#.
    ..#..)") == topology_counts{1, 1});
  // A one-pixel diamond: its single inside pixel is a hole.
  CHECK(topology_of(R"(
    .#.
    #.#
    .#.)") == topology_counts{1, 1});
  // A figure eight and a separate blob.
  CHECK(topology_of(R"(
    #####....
    #...#.##.
    #####.##.
    #...#....
    #####....)") == topology_counts{2, 2});
  // A C shape open to the border: its inside reaches the border, so no hole.
  CHECK(topology_of(R"(
    ####
    #...
    ####)") == topology_counts{1, 0});
  // A hole that touches the border only diagonally is still enclosed (4-connected background).
  CHECK(topology_of(R"(
    .####
    #...#
    #####)") == topology_counts{1, 1});
  // Checkerboard: one 8-connected component; the background pixels are 4-isolated, and the
  // interior ones are holes.
  CHECK(topology_of(R"(
    #.#.#
    .#.#.
    #.#.#
    .#.#.
    #.#.#)") == topology_counts{1, 4});
  // Nested rings with a dot inside.
  CHECK(topology_of(R"(
    #########
    #.......#
    #.#####.#
    #.#...#.#
    #.#.#.#.#
    #.#...#.#
    #.#####.#
    #.......#
    #########)") == topology_counts{3, 2});
}

TEST_CASE("count_topology: agrees with flood fill on random masks, dense and strided") {
  std::mt19937 rng(1234);
  std::uniform_int_distribution<int> size(1, 32);
  std::uniform_real_distribution<double> density(0.05, 0.95);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  workspace ws;
  int mismatches = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int w = size(rng);
    const int h = size(rng);
    const double p = density(rng);
    image<std::uint8_t> big(w + 4, h + 3, static_cast<std::uint8_t>(trial % 2));
    const auto mask = big.view().sub_view(1, 2, w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) mask(x, y) = coin(rng) < p ? 1 : 0;
    ws.reset();
    auto counts = perch::count_topology(image_view<const std::uint8_t>(mask), ws);
    REQUIRE(counts);
    const topology_counts expected = reference_topology(mask);
    if (!(*counts == expected) && ++mismatches <= 3) {
      INFO(perch::support::to_ascii(mask)
           << "perch " << counts->components << "/" << counts->holes << " reference "
           << expected.components << "/" << expected.holes);
      CHECK(false);
    }
  }
  CHECK(mismatches == 0);
}

TEST_CASE("count_topology: exact workspace, no allocation, bad input") {
  image<std::uint8_t> mask(40, 30, 0);
  for (int y = 0; y < 30; y += 2)
    for (int x = (y / 2) % 2; x < 40; x += 2) mask(x, y) = 1;
  const std::size_t bytes = perch::topology_workspace_bytes(40, 30);
  std::vector<std::byte> buffer(bytes + workspace::alignment);
  const auto skip = (workspace::alignment -
                     reinterpret_cast<std::uintptr_t>(buffer.data()) % workspace::alignment) %
                    workspace::alignment;
  {
    workspace exact{std::span<std::byte>(buffer.data() + skip, bytes)};
    const topology_counts expected = reference_topology(mask.view());
    perch::test::allocation_scope scope;
    auto counts = perch::count_topology(mask.view(), exact);
    CHECK(scope.count() == 0);
    REQUIRE(counts);
    CHECK(*counts == expected);
    CHECK(exact.used() == 0);
    CHECK(exact.high_water() == bytes);
  }
  {
    workspace small{std::span<std::byte>(buffer.data() + skip, bytes - workspace::alignment)};
    auto counts = perch::count_topology(mask.view(), small);
    REQUIRE(!counts);
    CHECK(counts.error().code == errc::workspace_too_small);
    CHECK(counts.error().needed == bytes);
    CHECK(small.used() == 0);
  }
  {
    workspace ws;
    REQUIRE(perch::count_topology(mask.view(), ws));
    perch::test::allocation_scope scope;
    REQUIRE(perch::count_topology(mask.view(), ws));
    CHECK(scope.count() == 0);
    image<std::uint8_t> empty;
    auto e = perch::count_topology(empty.view(), ws);
    REQUIRE(!e);
    CHECK(e.error().code == errc::empty_image);
    auto n = perch::count_topology(image_view<const std::uint8_t>(nullptr, 3, 3), ws);
    REQUIRE(!n);
    CHECK(n.error().code == errc::null_data);
    auto s = perch::count_topology(image_view<const std::uint8_t>(mask.data(), 40, 30, 10), ws);
    REQUIRE(!s);
    CHECK(s.error().code == errc::stride_too_small);
  }
}
