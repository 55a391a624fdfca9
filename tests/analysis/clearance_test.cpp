// SPDX-License-Identifier: BSL-1.0
#include "perch/analysis/clearance.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <random>

#include "perch/core/image.hpp"

namespace {
perch::window_measures at_scale(float mm_per_px) {
  perch::window_measures m;
  m.mm_per_px = mm_per_px;
  return m;
}
}  // namespace

TEST_CASE("clearance: band, box above and circle count other tree only") {
  // A horizontal branch along row 50 (radius 2), a twig block above-left, nothing elsewhere.
  perch::image<std::uint8_t> mask(200, 100, 0);
  for (int x = 0; x < 200; ++x)
    for (int y = 48; y <= 52; ++y) mask(x, y) = 1;
  for (int x = 40; x < 60; ++x)
    for (int y = 30; y < 40; ++y) mask(x, y) = 1;  // 200 px of twigs
  const perch::tree_pixel_counter tree(mask.view());
  CHECK(tree.count(50, 0, 199) == 200);
  CHECK(tree.count(35, -10, 45) == 6);
  CHECK(tree.count(500, 0, 10) == 0);

  const auto m = at_scale(1.0f);
  const perch::point2f up(0, -1);
  // Window on the right: nothing but its own branch around it.
  const perch::window_context right(tree, m, {140, 50}, {180, 50}, 2.5f, up);
  CHECK(right.band(20.0f).tree == 0);
  CHECK(right.band(20.0f).total > 0);
  CHECK(right.above(40.0f, 30.0f).share() == 0.0f);
  CHECK(right.circle(30.0f).share() == 0.0f);
  // Window under the twigs: all three see them.
  const perch::window_context left(tree, m, {30, 50}, {70, 50}, 2.5f, up);
  CHECK(left.band(20.0f).tree == 200);
  CHECK(left.above(40.0f, 30.0f).tree > 100);
  CHECK(left.circle(30.0f).tree > 100);
  // Scale: the same 20 mm margin at 4 mm/px is a 5 px band, which the twigs (≥ 10 px away
  // from the branch surface) do not reach.
  const auto coarse = at_scale(4.0f);
  const perch::window_context far(tree, coarse, {30, 50}, {70, 50}, 2.5f, up);
  CHECK(far.band(20.0f).tree == 0);
}

TEST_CASE("clearance: row counts equal a pixel-by-pixel count on random masks") {
  // Any non-zero byte is tree; intervals start and end anywhere, inside words or across them.
  std::mt19937 rng(11);
  const std::uint8_t values[] = {0, 0, 0, 1, 255, 128, 7};
  for (int round = 0; round < 200; ++round) {
    const int w = 1 + static_cast<int>(rng() % 70);
    perch::image<std::uint8_t> mask(w, 3, 0);
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < w; ++x) mask(x, y) = values[rng() % 7];
    const perch::tree_pixel_counter tree(mask.view());
    for (int q = 0; q < 20; ++q) {
      const int y = static_cast<int>(rng() % 5) - 1;
      const int x0 = static_cast<int>(rng() % static_cast<unsigned>(w + 10)) - 5;
      const int x1 = static_cast<int>(rng() % static_cast<unsigned>(w + 10)) - 5;
      std::uint32_t expected = 0;
      for (int x = x0; x <= x1; ++x)
        if (y >= 0 && y < 3 && x >= 0 && x < w && mask(x, y) != 0) ++expected;
      REQUIRE(tree.count(y, x0, x1) == expected);
    }
  }
}
