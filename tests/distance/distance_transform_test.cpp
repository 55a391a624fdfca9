// SPDX-License-Identifier: BSL-1.0
#include "perch/distance/distance_transform.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "allocation_counter.hpp"
#include "perch/core/image.hpp"
#include "perch/distance/detail/envelope.hpp"
#include "support/ascii_art.hpp"

using perch::errc;
using perch::image;
using perch::image_view;
using perch::pixel;
using perch::workspace;
using perch::support::mask_from_ascii;

namespace {

struct brute_result {
  image<std::uint32_t> dist2;
  image<pixel> nearest;
};

// Obviously correct: every pixel against every background pixel of the image and of the
// one-pixel frame around it (outside = background); ties to the smallest column, then row.
brute_result brute_force(image_view<const std::uint8_t> mask) {
  const int w = mask.width();
  const int h = mask.height();
  std::vector<pixel> background;
  for (int y = -1; y <= h; ++y)
    for (int x = -1; x <= w; ++x)
      if (!mask.contains(x, y) || mask(x, y) == 0) background.push_back({x, y});
  brute_result out{image<std::uint32_t>(w, h), image<pixel>(w, h)};
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::int64_t best = -1;
      pixel arg{};
      for (const pixel b : background) {
        const std::int64_t d = std::int64_t{b.x - x} * (b.x - x) + std::int64_t{b.y - y} * (b.y - y);
        if (best < 0 || d < best || (d == best && (b.x < arg.x || (b.x == arg.x && b.y < arg.y)))) {
          best = d;
          arg = b;
        }
      }
      out.dist2(x, y) = static_cast<std::uint32_t>(best);
      out.nearest(x, y) = arg;
    }
  return out;
}

image<std::uint8_t> random_mask(std::mt19937& rng, int w, int h, double density) {
  image<std::uint8_t> m(w, h);
  std::bernoulli_distribution ink(density);
  // Half the masks are blobs (thresholded smoothed noise) so distances exceed 1.
  if (rng() % 2 == 0) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) m(x, y) = ink(rng) ? 1 : 0;
  } else {
    std::uniform_int_distribution<int> cx(0, w - 1), cy(0, h - 1), r(0, 1 + (w + h) / 4);
    const int discs = 1 + static_cast<int>(rng() % 5);
    for (int k = 0; k < discs; ++k) {
      const int x0 = cx(rng), y0 = cy(rng), rr = r(rng);
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          if ((x - x0) * (x - x0) + (y - y0) * (y - y0) <= rr * rr) m(x, y) = 1;
    }
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        if (ink(rng) && ink(rng)) m(x, y) = static_cast<std::uint8_t>(1 - m(x, y));
  }
  return m;
}

image<std::uint32_t> fast_sq(image_view<const std::uint8_t> mask) {
  workspace ws;
  image<std::uint32_t> d(mask.width(), mask.height(), 12345);
  REQUIRE(perch::distance_transform_sq(mask, d.view(), ws));
  return d;
}

// Every squared variant (with nearest pixels, plain, foreground only) against `brute_force`.
void check_against_brute_force(image_view<const std::uint8_t> m) {
  const int w = m.width(), h = m.height();
  const auto ref = brute_force(m);
  workspace ws;
  image<std::uint32_t> d(w, h, 7);
  image<pixel> nearest(w, h, pixel{-9, -9});
  REQUIRE(perch::distance_transform_sq(m, d.view(), nearest.view(), ws));
  image<std::uint32_t> d_plain(w, h, 7);
  REQUIRE(perch::distance_transform_sq(m, d_plain.view(), ws));
  // The foreground-only variant: the same distances on the foreground, background untouched.
  image<std::uint32_t> d_fg(w, h, 7);
  REQUIRE(perch::distance_transform_sq_foreground(m, d_fg.view(), ws));
  // The same with the mask's runs listed; the runs of another image (here an empty one of the
  // same size) are not the mask's and must be ignored.
  const auto runs = perch::find_row_runs(m, ws, static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
  REQUIRE(runs);
  image<std::uint32_t> d_runs(w, h, 7);
  REQUIRE(perch::distance_transform_sq_foreground(m, d_runs.view(), ws, *runs));
  const image<std::uint8_t> blank(w, h);
  const auto other_runs = perch::find_row_runs(blank.view(), ws, 1);
  REQUIRE(other_runs);
  image<std::uint32_t> d_other(w, h, 7);
  REQUIRE(perch::distance_transform_sq_foreground(m, d_other.view(), ws, *other_runs));
  bool same = true;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      same = same && d(x, y) == ref.dist2(x, y) && d_plain(x, y) == ref.dist2(x, y) &&
             nearest(x, y) == ref.nearest(x, y) &&
             d_fg(x, y) == (m(x, y) != 0 ? ref.dist2(x, y) : 7u) && d_runs(x, y) == d_fg(x, y) &&
             d_other(x, y) == d_fg(x, y);
  CHECK_MESSAGE(same, "mask:\n" << perch::support::to_ascii(m));
}

}  // namespace

TEST_CASE("distance_transform_sq: ASCII cases") {
  SUBCASE("a 5-wide bar touching the left and right borders") {
    const auto m = mask_from_ascii(R"(
      .......
      #######
      #######
      #######
      #######
      #######
      .......)");
    const auto d = fast_sq(m.view());
    CHECK(d(3, 3) == 9);
    CHECK(d(3, 2) == 4);
    CHECK(d(3, 1) == 1);
    CHECK(d(0, 3) == 1);  // the border is background
    CHECK(d(1, 3) == 4);
    CHECK(d(3, 0) == 0);
  }
  SUBCASE("all foreground: distance to the frame outside") {
    image<std::uint8_t> m(5, 3, 1);
    const auto d = fast_sq(m.view());
    CHECK(d(0, 0) == 1);
    CHECK(d(2, 1) == 4);
    CHECK(d(1, 1) == 4);
    CHECK(d(4, 2) == 1);
  }
  SUBCASE("1x1 foreground and background") {
    image<std::uint8_t> one(1, 1, 1);
    CHECK(fast_sq(one.view())(0, 0) == 1);
    image<std::uint8_t> zero(1, 1, 0);
    CHECK(fast_sq(zero.view())(0, 0) == 0);
  }
  SUBCASE("empty mask gives zeros everywhere") {
    image<std::uint8_t> m(9, 4, 0);
    const auto d = fast_sq(m.view());
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 9; ++x) CHECK(d(x, y) == 0);
  }
  SUBCASE("a diagonal: distances in both axes") {
    const auto m = mask_from_ascii(R"(
      .........
      .#######.
      .#######.
      .#######.
      .........)");
    const auto d = fast_sq(m.view());
    CHECK(d(4, 2) == 4);
    CHECK(d(2, 2) == 4);
    CHECK(d(1, 2) == 1);
  }
}

TEST_CASE("distance_transform_sq: equals brute force on thousands of random masks") {
  std::mt19937 rng(20240611);
  const int sizes[][2] = {{1, 1}, {1, 7}, {7, 1}, {1, 40}, {40, 1}, {2, 2}, {3, 5}, {8, 8},
                          {13, 9}, {17, 23}, {31, 4}, {24, 24}};
  int compared = 0;
  for (int round = 0; round < 250; ++round)
    for (const auto& s : sizes) {
      const double density = std::uniform_real_distribution<double>(0.05, 0.98)(rng);
      const auto m = random_mask(rng, s[0], s[1], density);
      check_against_brute_force(m.view());
      ++compared;
    }
  CHECK(compared == 3000);
}

TEST_CASE("envelope intersections: floor division by a reciprocal is exact") {
  // The envelope divides by 2k through a table of 1 / (2k); the quotient must be the exact floor
  // for every sign and size of numerator, including integer quotients (where a rounded
  // estimate lands on either side) and numerators past double precision.
  std::mt19937_64 rng(52);
  std::vector<double> inverse(1 << 17);
  perch::detail::fill_inverse_twice(inverse.data(), 0, inverse.size() / 2);
  // In two parts, as the distance transform fills it (as far as its longest run needs).
  perch::detail::fill_inverse_twice(inverse.data(), inverse.size() / 2, inverse.size());
  int checked = 0;
  for (int round = 0; round < 200000; ++round) {
    const auto k = static_cast<std::int64_t>(1 + rng() % (inverse.size() - 1));
    const std::int64_t b = 2 * k;
    const int bits = static_cast<int>(rng() % 62);
    std::int64_t a = static_cast<std::int64_t>(rng() >> (63 - bits)) * (rng() % 2 == 0 ? 1 : -1);
    if (round % 3 == 0) a = (a / b) * b + static_cast<std::int64_t>(rng() % 3) - 1;  // near multiples
    std::int64_t floor = a / b;
    if (floor * b > a) --floor;
    REQUIRE(perch::detail::floor_div(a, b, inverse[static_cast<std::size_t>(k)]) == floor);
    ++checked;
  }
  CHECK(checked == 200000);
}

TEST_CASE("distance_transform_sq: equals brute force on thick shapes (long runs, tall columns)") {
  // Rows crossing a shape thicker than the windowed search's reach (both ways) take the parabola
  // envelope, which skips columns taller than half the run; these masks have such runs and
  // columns.
  std::mt19937 rng(20261125);
  const int sizes[][2] = {{48, 40}, {72, 56}, {40, 72}, {100, 24}, {180, 150}};
  int compared = 0;
  for (int round = 0; round < 10; ++round)
    for (const auto& s : sizes) {
      if (s[0] == 180 && round % 4 != 0) continue;  // brute force is slow there
      const auto m = random_mask(rng, s[0], s[1], 0.08);
      check_against_brute_force(m.view());
      ++compared;
    }
  CHECK(compared == 43);
}

TEST_CASE("windowed nearest-site search equals brute force, vector and one pixel at a time") {
  // Runs of 3-300 sites, background at both ends, heights from 0 to far above the run; the
  // search takes the least reach the distance transform would give it, or any larger one.
  std::mt19937 rng(1126);
  std::vector<std::uint32_t> g, vector_out, scalar_out;
  std::vector<std::int16_t> scratch;
  int compared = 0;
  for (int round = 0; round < 4000; ++round) {
    const int m = 3 + static_cast<int>(rng() % 298);
    const auto top = static_cast<std::uint32_t>(1 + rng() % (round % 3 == 0 ? 8 : 200));
    g.assign(static_cast<std::size_t>(m), 0);
    for (int u = 1; u + 1 < m; ++u)
      g[static_cast<std::size_t>(u)] = static_cast<std::uint32_t>(rng() % (top + 1));
    int reach = 0;
    for (int u = 1; u + 1 < m; ++u)
      reach = std::max(reach,
                       std::min({static_cast<int>(g[static_cast<std::size_t>(u)]), u, m - 1 - u}));
    if (reach > perch::detail::window_reach_limit) continue;
    if (round % 2 == 1)
      reach += static_cast<int>(
          rng() % static_cast<unsigned>(perch::detail::window_reach_limit - reach + 1));
    scratch.assign(perch::detail::window_scratch(static_cast<std::size_t>(m)), 0);
    vector_out.assign(static_cast<std::size_t>(m), 7);
    scalar_out.assign(static_cast<std::size_t>(m), 7);
    perch::detail::nearest_sites_window(g.data(), m, reach, scratch.data(), vector_out.data());
    perch::detail::nearest_sites_window<false>(g.data(), m, reach, scratch.data(),
                                               scalar_out.data());
    bool same = vector_out[0] == 7 && vector_out[static_cast<std::size_t>(m - 1)] == 7;
    for (int u = 1; u + 1 < m; ++u) {
      std::uint64_t best = ~std::uint64_t{0};
      for (int i = 0; i < m; ++i) {
        const std::uint64_t gi = g[static_cast<std::size_t>(i)];
        best = std::min(best, static_cast<std::uint64_t>((u - i) * (u - i)) + gi * gi);
      }
      same = same && vector_out[static_cast<std::size_t>(u)] == best &&
             scalar_out[static_cast<std::size_t>(u)] == best;
    }
    INFO("m = " << m << ", reach = " << reach);
    REQUIRE(same);
    ++compared;
  }
  CHECK(compared > 3500);
}

TEST_CASE("distance_transform_sq: columns 2^16 pixels deep (a height whose square wraps)") {
  // A strip three pixels wide down a 5 × 140 000 image: rows take the windowed search, whose
  // column heights reach 65 536 (and 74 464 from below), where a 32-bit square is 0 (it caps
  // them at its reach + 1 before squaring). Every
  // strip pixel is 1 from the side background (4 in the middle column) or nearer the ends.
  const int w = 5, h = 140000;
  image<std::uint8_t> m(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 1; x <= 3; ++x) m.view()(x, y) = 1;
  image<std::uint32_t> d(w, h);
  workspace ws;
  REQUIRE(perch::distance_transform_sq(image_view<const std::uint8_t>(m.view()), d.view(), ws));
  int wrong = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 1; x <= 3; ++x) {
      const std::int64_t vertical = std::min(y + 1, h - y);
      const std::int64_t side = std::min(x, w - 1 - x);
      wrong += d.view()(x, y) == std::min(vertical * vertical, side * side) ? 0 : 1;
    }
  CHECK(wrong == 0);
}

TEST_CASE(
    "distance_transform_sq: an image of 4 Mpx and more (rows fetched ahead) is tile by tile") {
  // From `detail::fetch_ahead_from` pixels on, both passes fetch rows ahead. A 2100 × 2100 image
  // of 15 × 15 tiles, each a random mask with a background frame of its own (so its distances
  // depend on it alone), must give every tile's own transform, background and runs alike.
  constexpr int tile_w = 140, tile_h = 140, tiles = 15;
  static_assert(std::size_t{tile_w * tiles} * std::size_t{tile_h * tiles} >=
                perch::detail::fetch_ahead_from);
  std::mt19937 rng(4242);
  std::vector<image<std::uint8_t>> masks;
  image<std::uint8_t> big(tile_w * tiles, tile_h * tiles, 0);
  for (int t = 0; t < tiles * tiles; ++t) {
    auto m = random_mask(rng, tile_w, tile_h, t % 2 == 0 ? 0.7 : 0.1);
    for (int y = 0; y < tile_h; ++y)
      for (int x = 0; x < tile_w; ++x) {
        if (x == 0 || y == 0 || x == tile_w - 1 || y == tile_h - 1) m(x, y) = 0;
        big((t % tiles) * tile_w + x, (t / tiles) * tile_h + y) = m(x, y);
      }
    masks.push_back(std::move(m));
  }
  const auto d = fast_sq(big.view());
  int wrong = 0;
  for (int t = 0; t < tiles * tiles; ++t) {
    const auto own = fast_sq(masks[static_cast<std::size_t>(t)].view());
    for (int y = 0; y < tile_h; ++y)
      for (int x = 0; x < tile_w; ++x)
        wrong += d((t % tiles) * tile_w + x, (t / tiles) * tile_h + y) == own(x, y) ? 0 : 1;
  }
  CHECK(wrong == 0);
}

TEST_CASE("distance_transform: anisotropic real distances equal brute force") {
  std::mt19937 rng(7);
  for (int round = 0; round < 400; ++round) {
    const int w = 1 + static_cast<int>(rng() % 20);
    const int h = 1 + static_cast<int>(rng() % 20);
    const auto m = random_mask(rng, w, h, 0.7);
    const perch::distance_options options{
        .spacing_x = std::uniform_real_distribution<float>(0.2f, 3.0f)(rng),
        .spacing_y = std::uniform_real_distribution<float>(0.2f, 3.0f)(rng)};
    workspace ws;
    image<float> d(w, h, -1.0f);
    REQUIRE(perch::distance_transform(m.view(), d.view(), ws, options));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        double best = 1e300;
        for (int by = -1; by <= h; ++by)
          for (int bx = -1; bx <= w; ++bx)
            if (!m.view().contains(bx, by) || m(bx, by) == 0) {
              const double dx = (bx - x) * static_cast<double>(options.spacing_x);
              const double dy = (by - y) * static_cast<double>(options.spacing_y);
              best = std::min(best, std::sqrt(dx * dx + dy * dy));
            }
        REQUIRE(static_cast<double>(d(x, y)) == doctest::Approx(best).epsilon(1e-5));
      }
  }
  SUBCASE("unit spacing is the square root of the squared transform") {
    const auto m = random_mask(rng, 50, 40, 0.9);
    const auto d2 = fast_sq(m.view());
    workspace ws;
    image<float> d(50, 40);
    REQUIRE(perch::distance_transform(m.view(), d.view(), ws));
    for (int y = 0; y < 40; ++y)
      for (int x = 0; x < 50; ++x)
        CHECK(d(x, y) == doctest::Approx(std::sqrt(static_cast<double>(d2(x, y)))));
  }
}

TEST_CASE("distance_transform_sq: strided views give the same answer as dense ones") {
  std::mt19937 rng(99);
  for (int round = 0; round < 200; ++round) {
    const int w = 1 + static_cast<int>(rng() % 30);
    const int h = 1 + static_cast<int>(rng() % 30);
    const auto m = random_mask(rng, w, h, 0.8);
    // The mask inside a larger buffer with garbage around it.
    image<std::uint8_t> big(w + 7, h + 5, 1);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) big(x + 3, y + 2) = m(x, y);
    const auto sub = big.view().sub_view(3, 2, w, h);
    image<std::uint32_t> out_big(w + 4, h + 3, 77);
    const auto out = out_big.view().sub_view(2, 1, w, h);
    workspace ws;
    REQUIRE(perch::distance_transform_sq(image_view<const std::uint8_t>(sub), out, ws));
    const auto dense = fast_sq(m.view());
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) REQUIRE(out(x, y) == dense(x, y));
    // Nothing outside the output view was written.
    for (int y = 0; y < h + 3; ++y)
      for (int x = 0; x < w + 4; ++x)
        if (!(x >= 2 && x < w + 2 && y >= 1 && y < h + 1)) REQUIRE(out_big(x, y) == 77);
  }
}

TEST_CASE("distance_transform_sq: bad input is a status") {
  image<std::uint8_t> m(4, 3, 1);
  image<std::uint32_t> d(4, 3);
  workspace ws;
  const image_view<const std::uint8_t> null_mask(nullptr, 4, 3);
  CHECK(perch::distance_transform_sq(null_mask, d.view(), ws).error().code == errc::null_data);
  const image_view<const std::uint8_t> bad_stride(m.data(), 4, 3, 2);
  CHECK(perch::distance_transform_sq(bad_stride, d.view(), ws).error().code ==
        errc::stride_too_small);
  const image_view<const std::uint8_t> empty(m.data(), 0, 3);
  CHECK(perch::distance_transform_sq(empty, d.view(), ws).error().code == errc::empty_image);
  image<std::uint32_t> small(3, 3);
  CHECK(perch::distance_transform_sq(m.view(), small.view(), ws).error().code ==
        errc::size_mismatch);
  image<pixel> near_small(4, 2);
  CHECK(perch::distance_transform_sq(m.view(), d.view(), near_small.view(), ws).error().code ==
        errc::size_mismatch);
  image<float> f(4, 3);
  CHECK(perch::distance_transform(m.view(), f.view(), ws, {.spacing_x = 0.0f}).error().detail ==
        "distance_options.spacing_x");
  CHECK(perch::distance_transform(m.view(), f.view(), ws, {.spacing_y = NAN}).error().code ==
        errc::invalid_parameter);
  // "Finite and positive": every finite spacing is taken, the infinite one is not.
  constexpr float largest = std::numeric_limits<float>::max();
  CHECK(perch::distance_options{.spacing_x = largest, .spacing_y = largest}.validate());
  CHECK(perch::distance_options{.spacing_x = 3.2e38f}.validate());
  CHECK(perch::distance_transform(m.view(), f.view(), ws, {.spacing_y = INFINITY}).error().detail ==
        "distance_options.spacing_y");
}

TEST_CASE("distance_transform_sq: workspace size is exact and the call allocates nothing") {
  const int w = 300;
  const int h = 200;
  image<std::uint8_t> m(w, h, 1);
  image<std::uint32_t> d(w, h);
  const std::size_t bytes = perch::distance_workspace_bytes(w, h);
  std::vector<std::byte> aligned(bytes + 64);
  auto* start = aligned.data();
  while (reinterpret_cast<std::uintptr_t>(start) % 64 != 0) ++start;
  {
    workspace fits{std::span<std::byte>(start, bytes)};
    perch::test::allocation_scope scope;
    CHECK(perch::distance_transform_sq(m.view(), d.view(), fits));
    CHECK(scope.count() == 0);
    CHECK(fits.high_water() == bytes);
    CHECK(fits.used() == 0);  // scratch is given back
  }
  {
    workspace too_small{std::span<std::byte>(start, bytes - 64)};
    const auto s = perch::distance_transform_sq(m.view(), d.view(), too_small);
    REQUIRE(!s);
    CHECK(s.error().code == errc::workspace_too_small);
    CHECK(s.error().needed == bytes);
  }
  workspace owning;
  REQUIRE(perch::distance_transform_sq(m.view(), d.view(), owning));
  image<pixel> nearest(w, h);
  image<float> real(w, h);
  REQUIRE(perch::distance_transform_sq(m.view(), d.view(), nearest.view(), owning));
  perch::test::allocation_scope scope;
  for (int k = 0; k < 3; ++k) {
    REQUIRE(perch::distance_transform_sq(m.view(), d.view(), owning));
    REQUIRE(perch::distance_transform_sq(m.view(), d.view(), nearest.view(), owning));
    REQUIRE(perch::distance_transform(m.view(), real.view(), owning));
  }
  CHECK(scope.count() == 0);
}
