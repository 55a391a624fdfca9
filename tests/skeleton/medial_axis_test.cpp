// SPDX-License-Identifier: BSL-1.0
#include "perch/skeleton/medial_axis.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "perch/core/image.hpp"
#include "perch/distance/distance_transform.hpp"
#include "support/ascii_art.hpp"

using perch::image;
using perch::image_view;
using perch::workspace;
using perch::support::to_ascii;

namespace {

// A strip of width `width_px` at `angle_deg` through the image centre: pixels whose centre lies
// within width/2 of the centre line, and within `half_length` along it.
image<std::uint8_t> strip(int size, double angle_deg, double width_px, double half_length) {
  image<std::uint8_t> m(size, size);
  const double a = angle_deg * std::numbers::pi / 180.0;
  const double ux = std::cos(a), uy = std::sin(a);
  const double c = (size - 1) / 2.0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const double dx = x - c, dy = y - c;
      const double along = dx * ux + dy * uy;
      const double across = -dx * uy + dy * ux;
      if (std::abs(across) <= width_px / 2.0 && std::abs(along) <= half_length) m(x, y) = 1;
    }
  return m;
}

struct result_images {
  image<std::uint32_t> d2;
  image<std::uint8_t> skeleton;
};

result_images run(const image<std::uint8_t>& m) {
  workspace ws;
  result_images r{image<std::uint32_t>(m.width(), m.height()), image<std::uint8_t>(m.width(), m.height())};
  REQUIRE(perch::distance_transform_sq(m.view(), r.d2.view(), ws));
  REQUIRE(perch::medial_axis{}(m.view(), r.d2.view(), r.skeleton.view(), ws));
  return r;
}

}  // namespace

TEST_CASE("medial_axis: diameter 2d-1 on the axis of a strip follows its width at every angle") {
  int checked = 0;
  for (const double width : {5.0, 7.0, 9.0, 12.0, 16.0}) {
    for (int angle = 0; angle <= 90; angle += 5) {
      const auto m = strip(101, angle, width, 38.0);
      const auto r = run(m);
      const double c = 50.0;
      const double a = angle * std::numbers::pi / 180.0;
      int pixels = 0;
      int off = 0;
      double worst = 0, sum = 0;
      for (int y = 0; y < 101; ++y)
        for (int x = 0; x < 101; ++x) {
          if (!r.skeleton(x, y)) continue;
          const double along = (x - c) * std::cos(a) + (y - c) * std::sin(a);
          if (std::abs(along) > 38.0 - width) continue;  // away from the ends
          const double diameter = 2.0 * std::sqrt(static_cast<double>(r.d2(x, y))) - 1.0;
          ++pixels;
          // 2d − 1 is exact for axis-aligned strips; at oblique angles the background pixel
          // centres lie 0 … 1 px beyond the edge and the axis pixel up to ½ px off the centre
          // line, so one pixel's diameter can be off by up to 2 px; the mean is within ±1.25.
          if (std::abs(diameter - width) > 2.0 + 1e-9) ++off;
          worst = std::max(worst, std::abs(diameter - width));
          sum += diameter - width;
        }
      INFO("width " << width << " angle " << angle);
      CHECK(pixels > 20);
      CHECK(off == 0);
      CHECK(worst <= 2.0);
      CHECK(std::abs(sum / pixels) <= 1.25);
      if (angle % 90 == 0 && static_cast<int>(width) % 2 == 1) CHECK(worst == 0.0);
      ++checked;
    }
  }
  CHECK(checked == 5 * 19);
}

TEST_CASE("medial_axis: on the ridge and reaching near the tips of thick strokes") {
  for (int angle = 0; angle <= 90; angle += 15) {
    const double width = 11.0;
    const double half = 30.0;
    const auto m = strip(91, angle, width, half);
    const auto r = run(m);
    const double c = 45.0;
    const double a = angle * std::numbers::pi / 180.0;
    double min_along = 1e9, max_along = -1e9;
    for (int y = 0; y < 91; ++y)
      for (int x = 0; x < 91; ++x) {
        if (!r.skeleton(x, y)) continue;
        const double along = (x - c) * std::cos(a) + (y - c) * std::sin(a);
        const double across = -(x - c) * std::sin(a) + (y - c) * std::cos(a);
        min_along = std::min(min_along, along);
        max_along = std::max(max_along, along);
        if (std::abs(along) < half - width) CHECK(std::abs(across) <= 1.0);  // on the ridge
      }
    INFO("angle " << angle << "\n" << to_ascii(r.skeleton.view()));
    // The tips: within one radius (plus a pixel) of the stroke's ends.
    CHECK(max_along >= half - (width / 2.0 + 1.5));
    CHECK(min_along <= -half + (width / 2.0 + 1.5));
  }
}

TEST_CASE("medial_axis: ridge pixels are local maxima of dist2 across the stroke within 1 px") {
  const auto m = perch::support::mask_from_ascii(R"(
    ....................
    .##################.
    .##################.
    .##################.
    .##################.
    .##################.
    .##################.
    .##################.
    ....................)");
  const auto r = run(m);
  for (int x = 4; x < 16; ++x) {
    int rows = 0;
    for (int y = 0; y < m.height(); ++y)
      if (r.skeleton(x, y)) {
        ++rows;
        CHECK(y == 4);  // the middle row, where dist2 is largest
      }
    CHECK(rows == 1);
  }
}

TEST_CASE("medial_axis: two thick diagonal strokes crossing give one thin connected cross") {
  image<std::uint8_t> m(60, 60);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 60; ++x)
      if (std::abs(x - y) <= 3 || std::abs(x + y - 59) <= 3) m(x, y) = 1;
  const auto r = run(m);
  int count = 0;
  for (int y = 0; y + 1 < 60; ++y)
    for (int x = 0; x + 1 < 60; ++x) {
      count += r.skeleton(x, y);
      CHECK_FALSE((r.skeleton(x, y) && r.skeleton(x + 1, y) && r.skeleton(x, y + 1) &&
                   r.skeleton(x + 1, y + 1)));
    }
  CHECK(count > 100);
}

TEST_CASE("medial_axis: a mask with a background frame gives the same skeleton in place") {
  // A background frame lets the medial axis thin in its output and read dist2 by index; a
  // wider output stride or a dist2 laid out differently takes the padded copy or positions.
  std::mt19937 rng(913);
  workspace ws;
  for (int round = 0; round < 300; ++round) {
    const int w = 3 + static_cast<int>(rng() % 40);
    const int h = 3 + static_cast<int>(rng() % 40);
    image<std::uint8_t> m(w, h);
    std::bernoulli_distribution ink(std::uniform_real_distribution<double>(0.3, 0.95)(rng));
    for (int y = 1; y + 1 < h; ++y)
      for (int x = 1; x + 1 < w; ++x) m(x, y) = ink(rng) ? static_cast<std::uint8_t>(1 + rng() % 3) : 0;
    image<std::uint32_t> d2(w, h);
    REQUIRE(perch::distance_transform_sq(m.view(), d2.view(), ws));
    image<std::uint8_t> in_place(w, h, 7);
    REQUIRE(perch::medial_axis{}(m.view(), d2.view(), in_place.view(), ws));
    image<std::uint32_t> d2_wide(w + 5, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) d2_wide(x, y) = d2(x, y);
    image<std::uint8_t> by_position(w, h, 7);
    REQUIRE(perch::medial_axis{}(m.view(), d2_wide.view().sub_view(0, 0, w, h), by_position.view(), ws));
    image<std::uint8_t> wide(w + 9, h, 7);
    const auto padded = wide.view().sub_view(0, 0, w, h);
    REQUIRE(perch::medial_axis{}(m.view(), d2.view(), padded, ws));
    bool same = true, binary = true;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        same = same && in_place(x, y) == padded(x, y) && by_position(x, y) == padded(x, y);
        binary = binary && in_place(x, y) <= 1;
      }
    INFO("mask:\n" << to_ascii(m.view()) << "in place:\n" << to_ascii(in_place.view())
                   << "padded:\n" << to_ascii(padded));
    CHECK(same);
    CHECK(binary);
    CHECK(ws.used() == 0);
  }
}

TEST_CASE(
    "medial_axis: a map of zeros peels at one key, its ring wrapping, as the linked lists did") {
  // With every distance 0 the whole peeling happens at one key: after the border, each pixel is
  // queued while that key is emptied, so it goes round the ring (here more pixels pass through
  // it than it has slots, so it wraps). The expected skeleton is the one the linked-list queue
  // (27612bc) gave for this mask; the mask's frame is not background, so this is the padded copy.
  const auto mask = perch::support::mask_from_ascii(R"(
      ############################################
      ############################.###############
      ##############################.############.
      #########################################.##
      ##########################################.#
      #####################.######################
      ######.#####################################
      ####.##################.####################
      #########################.##################
      ######.##################################.##
      ############################################
      ############################################
      ############################################
      #######.####.###############################
      ################################.#######.###
      ################.####.######################
      ###############.#########.##################
      ############################################
      #############################.##############
      #####.##################.#.#################
      ###################.########################
      ###################################.########
      ##########################################.#
      ############################################
      #################.##############.###########
      ##########################################..
      #################.##############.###########
      ############################################
      ############################################
      ############################################
      ##################.#########################
      #.##########################.###############
      #######..###########################.#######
      ############################################
      #########################.######.###########
      ################.###########################
      ##.######.##########.#.##.######.####.######
      ######################.#####################
      ############################################
  )");
  const std::string expected = to_ascii(perch::support::mask_from_ascii(R"(
      ............................#...............
      ...........................#.###.........#..
      ....................###...#..#..#......##.#.
      ....####..........##...#.#..#....#....#...#.
      ...#....##.......#......#.##......#..#...#.#
      ..#.#.....#.....#......#...#.......##...#..#
      ..#..#.....#.#.#......#...#.#.......#####.#.
      ..#...#.....#.#......#...#...#.....#.....#..
      ..#..#.#...#...#....#...#.....#.####......#.
      ..#.#...#.#.....#..#...#.......#....#......#
      ...#.....#.......##...#.......#......#....#.
      ...#...##.#......#.####......#......#.##.#..
      ...#.##...#.....#..#...##.###.......#...#...
      ....#.....#....#...#.....#..#.......#....#..
      ...#......#....#...#....#...#.......#.....#.
      ...#.....#....##...#....#....#......#....#..
      ....###..#...#..#..#...#....#.#.....#....#..
      ...#...#..#.#....###....#.#.#..#...#.#..#...
      ..#.....#..#.....#..#.##.#.#....#.#...#.#...
      ..#......##.....#....#...#..#....#.....#.#..
      ..#.......#....#.....#...#..#...#......#..#.
      ...#......#..##.#....#...#...#.#.......#...#
      ...#.......##....#....#..#...##.#......#...#
      ....#......#......#....#.#..#....#.....#...#
      .....#....#........#....##.#......#....####.
      ......#...#.#######.#...#.########.#..#.....
      .....#.###.#.........#.#...#........##......
      ....#..#...#..........#.....#........#......
      ...#..#.....#.....#....#.....#......#.#.....
      ..#..#......#...##.####.......#....#...#....
      .#...#.......#.#.......#.......#.##.....#...
      #...#.........##......#.#.......#.......#...
      .#..#........#..#.....#..#.....#.#......#...
      ..##........#....##.##....#...#..#......#...
      ..#.#....#..#......#..#....#.#....#..#..#...
      .#...#..#.##.......#.#.#.##.#..####.#.##....
      .#...###....##....#..#..#...###....#....##..
      .#.##...#.##..####.#.#..#.##...#.##.#.##..#.
      ..#......#..........#.##.#......#....#.....#
  )")
                                            .view());
  REQUIRE(mask.width() == 44);
  REQUIRE(mask.height() == 39);
  image<std::uint32_t> zeros(mask.width(), mask.height(), 0);
  image<std::uint8_t> out(mask.width(), mask.height(), 7);
  workspace ws;
  REQUIRE(perch::medial_axis{}(mask.view(), zeros.view(), out.view(), ws));
  CHECK(to_ascii(out.view()) == expected);
}

TEST_CASE("medial_axis: the packed peeling gives the skeletons of the byte image") {
  // `packed_from = 0` peels every image in the packed copy (flags and key in two bytes, keys of
  // 0x3FFF and more looked up in the map): same skeletons, in place and padded, with true maps
  // and random ones whose keys cross the packed range (images of 256 px and more can hold them),
  // scanning the mask and from its listed runs.
  std::mt19937 rng(4099);
  workspace ws;
  int large_keys = 0;
  for (int round = 0; round < 240; ++round) {
    const bool large = round % 8 == 7;
    const int w = large ? 256 + static_cast<int>(rng() % 64) : 3 + static_cast<int>(rng() % 40);
    const int h = large ? 256 + static_cast<int>(rng() % 64) : 3 + static_cast<int>(rng() % 40);
    const bool frame = round % 2 == 0;
    image<std::uint8_t> m(w, h);
    std::bernoulli_distribution ink(std::uniform_real_distribution<double>(0.3, 0.98)(rng));
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        m(x, y) = (frame && (x == 0 || y == 0 || x == w - 1 || y == h - 1)) || !ink(rng) ? 0 : 1;
    image<std::uint32_t> d2(w, h);
    REQUIRE(perch::distance_transform_sq(m.view(), d2.view(), ws));
    if (round % 3 != 0)
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          d2(x, y) = round % 3 == 1 ? static_cast<std::uint32_t>(rng() % 100000)
                                    : 0x3FF0u + static_cast<std::uint32_t>(rng() % 32);
          large_keys += m(x, y) != 0 && d2(x, y) >= 0x3FFFu && large;
        }
    image<std::uint8_t> bytes(w, h, 7), packed(w, h, 7), listed(w, h, 7);
    REQUIRE(perch::medial_axis{}(m.view(), d2.view(), bytes.view(), ws));
    REQUIRE(perch::medial_axis{.packed_from = 0}(m.view(), d2.view(), packed.view(), ws));
    {  // with the mask's runs listed (as find_perch gives them): the packed copy set up from them
      const auto mv = image_view<const std::uint8_t>(m.view());
      const auto runs =
          perch::find_row_runs(mv, ws, static_cast<std::size_t>(w) * static_cast<std::size_t>(h));
      REQUIRE(runs);
      REQUIRE(perch::medial_axis{.packed_from = 0}(mv, d2.view(), listed.view(), ws,
                                                   *runs));
      ws.reset();
    }
    INFO("round " << round << ", mask:\n" << to_ascii(m.view()));
    CHECK(to_ascii(packed.view()) == to_ascii(bytes.view()));
    CHECK(to_ascii(listed.view()) == to_ascii(bytes.view()));
    CHECK(ws.used() == 0);
  }
  CHECK(large_keys > 100000);
}
