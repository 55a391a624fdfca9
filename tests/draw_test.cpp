// SPDX-License-Identifier: BSL-1.0
#include "support/draw.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <vector>

#include "perch/core/image.hpp"
#include "support/ascii_art.hpp"
#include "support/font.hpp"

using perch::image;
using perch::image_view;
using perch::support::draw_point;
using perch::support::rgb;
using perch::support::rotated_rect;
namespace colours = perch::support::colours;

namespace {

constexpr rgb ink{255, 255, 255};

/// The canvas as ASCII art: '#' where a pixel is not black.
std::string art(const image<rgb>& canvas) {
  std::string out;
  for (int y = 0; y < canvas.height(); ++y) {
    for (int x = 0; x < canvas.width(); ++x) out += canvas(x, y) == rgb{} ? '.' : '#';
    out += '\n';
  }
  return out;
}

/// `expected` ASCII art normalised like mask_from_ascii, then printed as art.
std::string picture(std::string_view expected) {
  const auto mask = perch::support::mask_from_ascii(expected);
  std::string out;
  for (int y = 0; y < mask.height(); ++y) {
    for (int x = 0; x < mask.width(); ++x) out += mask(x, y) ? '#' : '.';
    out += '\n';
  }
  return out;
}

int count_lit(const image<rgb>& canvas) {
  int n = 0;
  for (int y = 0; y < canvas.height(); ++y)
    for (int x = 0; x < canvas.width(); ++x) n += canvas(x, y) == rgb{} ? 0 : 1;
  return n;
}

/// A pixel type other than `rgb`, laid out like perch::png::rgb8.
struct other_pixel {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
};
static_assert(perch::support::RgbPixel<rgb>);
static_assert(perch::support::RgbPixel<other_pixel>);
static_assert(!perch::support::RgbPixel<int>);
static_assert(!perch::support::RgbPixel<std::uint8_t>);

}  // namespace

TEST_CASE("put_pixel: blends with alpha and ignores pixels off the canvas") {
  image<rgb> c(4, 3);
  auto v = c.view();
  perch::support::put_pixel(v, 1, 1, rgb{200, 100, 50});
  CHECK(c(1, 1) == rgb{200, 100, 50});
  perch::support::put_pixel(v, 2, 1, rgb{255, 255, 255}, 0.5f);
  CHECK(c(2, 1) == rgb{128, 128, 128});
  perch::support::put_pixel(v, 2, 1, rgb{0, 0, 0}, 0.25f);
  CHECK(c(2, 1) == rgb{96, 96, 96});
  perch::support::put_pixel(v, 3, 2, ink, std::numeric_limits<float>::quiet_NaN());
  perch::support::put_pixel(v, 3, 2, ink, -1.0f);
  CHECK(c(3, 2) == rgb{});
  perch::support::put_pixel(v, 3, 2, ink, 7.0f);  // clamped to 1
  CHECK(c(3, 2) == ink);
  for (int x : {-1, 4, -2147483647 - 1, 2147483647})
    for (int y : {-1, 3, 0})
      perch::support::put_pixel(v, x, y, ink);
  CHECK(count_lit(c) == 3);
  CHECK(perch::support::get_pixel(v, 1, 1) == rgb{200, 100, 50});
  CHECK(perch::support::get_pixel(v, -5, 1) == rgb{});
}

TEST_CASE("fill_circle: discs sampled at pixel centres") {
  image<rgb> c(7, 7);
  perch::support::fill_circle(c.view(), {3, 3}, 0.0f, ink);
  CHECK(count_lit(c) == 1);
  perch::support::fill_circle(c.view(), {3, 3}, 1.0f, ink);
  CHECK(art(c) == picture(R"(
    .......
    .......
    ...#...
    ..###..
    ...#...
    .......
    .......
  )"));
  perch::support::fill_circle(c.view(), {3, 3}, 2.0f, ink);
  CHECK(art(c) == picture(R"(
    .......
    ...#...
    ..###..
    .#####.
    ..###..
    ...#...
    .......
  )"));
  perch::support::fill_circle(c.view(), {3, 3}, 3.0f, ink);
  CHECK(art(c) == picture(R"(
    ...#...
    .#####.
    .#####.
    #######
    .#####.
    .#####.
    ...#...
  )"));
  // A disc's area approaches pi r^2.
  image<rgb> big(101, 101);
  perch::support::fill_circle(big.view(), {50, 50}, 40.0f, ink);
  CHECK(std::abs(count_lit(big) - 3.14159265 * 1600) < 3.14159265 * 2 * 40);
}

TEST_CASE("draw_circle: a closed ring around the centre, hollow inside") {
  image<rgb> c(21, 21);
  perch::support::draw_circle(c.view(), {10, 10}, 8.0f, ink);
  CHECK(c(10, 10) == rgb{});
  CHECK(c(10, 2) == ink);
  CHECK(c(18, 10) == ink);
  CHECK(c(2, 10) == ink);
  CHECK(c(10, 18) == ink);
  // Every ray from the centre meets the ring (no gaps): walk outwards at many angles.
  for (int k = 0; k < 360; ++k) {
    const double a = k * 3.14159265358979 / 180.0;
    bool hit = false;
    for (double r = 0.0; r < 10.5 && !hit; r += 0.05) {
      const int x = static_cast<int>(std::lround(10 + r * std::cos(a)));
      const int y = static_cast<int>(std::lround(10 + r * std::sin(a)));
      hit = c(x, y) == ink;
    }
    CHECK(hit);
  }
  const int thin = count_lit(c);
  perch::support::draw_circle(c.view(), {10, 10}, 8.0f, ink, 3.0f);
  CHECK(count_lit(c) > 2 * thin);
  CHECK(c(10, 10) == rgb{});
}

TEST_CASE("draw_line: Bresenham lines between the nearest pixels") {
  image<rgb> c(8, 5);
  perch::support::draw_line(c.view(), {0, 0}, {7, 4}, ink);
  CHECK(art(c) == picture(R"(
    #.......
    .##.....
    ...##...
    .....##.
    .......#
  )"));
  image<rgb> d(5, 5);
  perch::support::draw_line(d.view(), {2, 4}, {2, 0}, ink);
  perch::support::draw_line(d.view(), {0, 2.4f}, {4, 1.6f}, ink);
  CHECK(art(d) == picture(R"(
    ..#..
    ..#..
    #####
    ..#..
    ..#..
  )"));
  // A single point.
  image<rgb> e(3, 3);
  perch::support::draw_line(e.view(), {1, 1}, {1, 1}, ink);
  CHECK(count_lit(e) == 1);
}

TEST_CASE("draw_line: random lines are 8-connected with max(|dx|, |dy|) + 1 pixels") {
  std::mt19937 rng(42u);
  std::uniform_int_distribution<int> coord(0, 39);
  for (int round = 0; round < 200; ++round) {
    image<rgb> c(40, 40);
    const int x0 = coord(rng), y0 = coord(rng), x1 = coord(rng), y1 = coord(rng);
    perch::support::draw_line(c.view(), {static_cast<float>(x0), static_cast<float>(y0)},
                              {static_cast<float>(x1), static_cast<float>(y1)}, ink);
    CHECK(count_lit(c) == std::max(std::abs(x1 - x0), std::abs(y1 - y0)) + 1);
    CHECK(c(x0, y0) == ink);
    CHECK(c(x1, y1) == ink);
    // Every lit pixel except the two ends has at least two lit 8-neighbours... or one for a
    // two-pixel line; the ends have exactly one when the line is longer than one pixel.
    if (x0 != x1 || y0 != y1) {
      for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 40; ++x) {
          if (!(c(x, y) == ink)) continue;
          int n = 0;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
              if ((dx != 0 || dy != 0) && c.view().contains(x + dx, y + dy) &&
                  c(x + dx, y + dy) == ink)
                ++n;
          CHECK(n >= 1);
        }
    }
  }
}

TEST_CASE("draw_line: clipping keeps the visible part of far-away lines") {
  image<rgb> c(10, 6);
  perch::support::draw_line(c.view(), {-1e9f, 3}, {1e9f, 3}, ink);
  for (int x = 0; x < 10; ++x) CHECK(c(x, 3) == ink);
  CHECK(count_lit(c) == 10);
  image<rgb> d(10, 10);
  perch::support::draw_line(d.view(), {-1e7f, -1e7f}, {1e7f, 1e7f}, ink);
  for (int i = 0; i < 10; ++i) CHECK(d(i, i) == ink);
  CHECK(count_lit(d) == 10);
}

TEST_CASE("thick lines, polylines and rotated rectangles") {
  image<rgb> c(12, 7);
  perch::support::draw_line(c.view(), {2, 3}, {9, 3}, ink, 3.0f);
  CHECK(art(c) == picture(R"(
    ............
    ............
    .##########.
    .##########.
    .##########.
    ............
    ............
  )"));

  image<rgb> p(7, 7);
  const std::array<draw_point, 4> pts{{{0, 0}, {6, 0}, {6, 6}, {0, 6}}};
  perch::support::draw_polyline(p.view(), std::span<const draw_point>(pts), rgb{255, 0, 0}, 1.0f,
                                0.5f);
  // Joints are plotted once: every lit pixel has the same half-blended colour.
  for (int y = 0; y < 7; ++y)
    for (int x = 0; x < 7; ++x)
      if (!(p(x, y) == rgb{})) CHECK(p(x, y) == rgb{128, 0, 0});
  CHECK(count_lit(p) == 6 + 6 + 6 + 1);

  // Axis-aligned rectangle: 6 x 3 centred on (5, 3).
  image<rgb> r(11, 7);
  perch::support::fill_rotated_rect(r.view(), rotated_rect{{5, 3}, 6.0f, 3.0f, 0.0f}, ink);
  CHECK(art(r) == picture(R"(
    ...........
    ...........
    ..#######..
    ..#######..
    ..#######..
    ...........
    ...........
  )"));
  // Rotated by 90 degrees: the transpose.
  image<rgb> t(7, 11);
  perch::support::fill_rotated_rect(t.view(), rotated_rect{{3, 5}, 6.0f, 3.0f, 90.0f}, ink);
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 7; ++x) CHECK(t(x, y) == r(y, x));

  // 45 degrees: area about length x width, centre and ends lit, corners of the box not.
  image<rgb> d(41, 41);
  perch::support::fill_rotated_rect(d.view(), rotated_rect{{20, 20}, 30.0f, 8.0f, 45.0f}, ink);
  CHECK(std::abs(count_lit(d) - 240) < 50);
  CHECK(d(20, 20) == ink);
  CHECK(d(29, 29) == ink);
  CHECK(d(11, 11) == ink);
  CHECK(d(29, 11) == rgb{});
  const auto corners = perch::support::corners(rotated_rect{{20, 20}, 30.0f, 8.0f, 45.0f});
  CHECK(std::abs(corners[0].x - (20 - 10.6066f + 2.8284f)) < 1e-3f);

  // Outline: hollow, and each pixel blended once (uniform tint).
  image<rgb> o(21, 21);
  perch::support::draw_rotated_rect(o.view(), rotated_rect{{10, 10}, 14.0f, 8.0f, 30.0f},
                                    rgb{0, 200, 0}, 2.0f, 0.5f);
  CHECK(o(10, 10) == rgb{});
  std::set<int> greens;
  for (int y = 0; y < 21; ++y)
    for (int x = 0; x < 21; ++x)
      if (!(o(x, y) == rgb{})) greens.insert(o(x, y).g);
  CHECK(greens == std::set<int>{100});
}

TEST_CASE("drawing anything, anywhere, never writes outside the view") {
  // A 20 x 16 view inside a 40 x 36 image whose border must stay untouched.
  constexpr rgb sentinel{1, 2, 3};
  image<rgb> backing(40, 36, sentinel);
  const image_view<rgb> view = backing.view().sub_view(10, 10, 20, 16);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  const float huge = 3e38f;
  std::vector<float> coords{-1e30f, -1e9f, -1e4f, -50.0f, -1.0f, -0.5f, 0.0f, 7.3f, 19.5f,
                            20.0f,  45.0f, 1e6f,  1e9f,  huge,  -huge, inf,  -inf, nan};
  std::mt19937 rng(99u);
  std::uniform_int_distribution<std::size_t> pick(0, coords.size() - 1);
  for (int round = 0; round < 3000; ++round) {
    const draw_point a{coords[pick(rng)], coords[pick(rng)]};
    const draw_point b{coords[pick(rng)], coords[pick(rng)]};
    const float size = coords[pick(rng)];
    const float angle = coords[pick(rng)];
    const rgb colour{static_cast<std::uint8_t>(round), 200, 100};
    perch::support::put_pixel(view, static_cast<int>(round * 7919) - 100000, round - 1500, colour);
    perch::support::draw_line(view, a, b, colour);
    perch::support::draw_line(view, a, b, colour, std::abs(size), 0.5f);
    perch::support::fill_circle(view, a, size, colour);
    perch::support::draw_circle(view, b, size, colour, std::abs(angle));
    perch::support::fill_rotated_rect(view, rotated_rect{a, size, std::abs(size), angle}, colour);
    perch::support::draw_rotated_rect(view, rotated_rect{b, std::abs(size), size, angle}, colour,
                                      std::abs(size));
    const std::array<draw_point, 3> poly{{a, b, {a.x, b.y}}};
    perch::support::draw_polyline(view, std::span<const draw_point>(poly), colour, size);
    const int ix = static_cast<int>(round * 104729) ;
    perch::support::fill_rect(view, ix, -ix, 2147483647, 2147483647, colour);
    perch::support::draw_rect(view, -ix, ix / 3, round * 1000, 2147483647, colour, round);
    perch::support::draw_colour_bar(view, ix, 3, 2147483647, round);
    perch::support::draw_text(view, ix, -ix / 2, "Hello, perch!\n~xyz~", colour,
                              perch::support::text_options{.scale = round % 80,
                                                           .background = colours::black,
                                                           .padding_px = round});
    const std::array<perch::support::legend_entry, 2> entries{
        {{"skeleton", colour, perch::support::legend_marker::ramp},
         {"perch", colour, perch::support::legend_marker::dot}}};
    perch::support::draw_legend(view, ix / 5, -ix / 7, std::span(entries),
                                perch::support::legend_options{.scale = round % 70});
  }
  for (int y = 0; y < backing.height(); ++y)
    for (int x = 0; x < backing.width(); ++x) {
      const bool inside = x >= 10 && x < 30 && y >= 10 && y < 26;
      if (!inside) CHECK(backing(x, y) == sentinel);
    }
  // And an empty canvas takes anything.
  image<rgb> empty;
  perch::support::fill_circle(empty.view(), {0, 0}, 5.0f, ink);
  perch::support::draw_line(empty.view(), {0, 0}, {5, 5}, ink);
  perch::support::draw_text(empty.view(), 0, 0, "x", ink);
}

TEST_CASE("paint_mask and dim make a quiet background") {
  const auto mask = perch::support::mask_from_ascii(R"(
    .##.
    ####
  )");
  image<rgb> c(5, 3, rgb{9, 9, 9});
  perch::support::paint_mask(mask.view(), c.view(), rgb{200, 200, 200}, rgb{10, 20, 30});
  CHECK(c(0, 0) == rgb{10, 20, 30});
  CHECK(c(1, 0) == rgb{200, 200, 200});
  CHECK(c(3, 1) == rgb{200, 200, 200});
  CHECK(c(4, 2) == rgb{9, 9, 9});  // outside the mask: untouched

  image<rgb> photo(2, 1);
  photo(0, 0) = rgb{200, 0, 0};
  photo(1, 0) = rgb{100, 100, 100};
  perch::support::dim(photo.view(), {.saturation = 0.0f, .towards = colours::black, .amount = 0.5f});
  CHECK(photo(0, 0) == rgb{30, 30, 30});  // luma 59.8, halved
  CHECK(photo(1, 0) == rgb{50, 50, 50});
  perch::support::dim(photo.view(), {.saturation = 1.0f, .towards = colours::white, .amount = 1.0f});
  CHECK(photo(0, 0) == colours::white);

  // On another pixel type.
  image<other_pixel> o(3, 3);
  perch::support::fill(o.view(), rgb{1, 2, 3});
  perch::support::fill_circle(o.view(), {1, 1}, 0.0f, rgb{7, 8, 9});
  CHECK(o(1, 1).r == 7);
  CHECK(o(0, 0).b == 3);
}

TEST_CASE("colour_map: endpoints, clamping, monotone luminance") {
  using perch::support::colour_map;
  using perch::support::colour_ramp;
  CHECK(colour_map(0.0f) == rgb{72, 20, 96});
  CHECK(colour_map(1.0f) == rgb{240, 226, 40});
  CHECK(colour_map(-3.0f) == colour_map(0.0f));
  CHECK(colour_map(9.0f) == colour_map(1.0f));
  CHECK(colour_map(std::numeric_limits<float>::quiet_NaN()) == colour_map(0.0f));
  CHECK(colour_map(0.5f, colour_ramp::gray) == rgb{128, 128, 128});
  CHECK(colour_map(15.0f, 10.0f, 20.0f) == colour_map(0.5f));
  CHECK(colour_map(15.0f, 10.0f, 10.0f) == colour_map(0.0f));
  double previous = -1.0;
  for (int i = 0; i <= 1000; ++i) {
    const rgb c = colour_map(static_cast<float>(i) / 1000.0f);
    const double luma = 0.299 * c.r + 0.587 * c.g + 0.114 * c.b;
    CHECK(luma >= previous - 0.6);  // rounding may wobble by under a level
    previous = luma;
  }
  image<rgb> bar(11, 2);
  perch::support::draw_colour_bar(bar.view(), 0, 0, 11, 2);
  CHECK(bar(0, 0) == colour_map(0.0f));
  CHECK(bar(10, 1) == colour_map(1.0f));
  CHECK(bar(5, 0) == colour_map(0.5f));
}

TEST_CASE("font: every printable glyph is distinct and non-empty except space") {
  std::set<perch::support::glyph> seen;
  for (int c = 32; c <= 126; ++c) {
    const auto& g = perch::support::glyph_for(static_cast<char>(c));
    bool empty = true;
    for (std::uint8_t row : g) {
      CHECK(row < 32);  // five columns
      if (row != 0) empty = false;
    }
    CHECK(empty == (c == ' '));
    CHECK(seen.insert(g).second);
  }
  CHECK(seen.size() == 95);
  CHECK(perch::support::glyph_for('\x01') == perch::support::glyph_for('?'));
  CHECK(perch::support::glyph_for('\xe9') == perch::support::glyph_for('?'));
}

TEST_CASE("draw_text: glyph pixels, metrics, scale and background box") {
  using perch::support::text_height;
  using perch::support::text_width;
  CHECK(text_width("") == 0);
  CHECK(text_width("A") == 5);
  CHECK(text_width("AB") == 11);
  CHECK(text_width("AB", 2) == 22);
  CHECK(text_width("ABC\nD") == 17);
  CHECK(text_height("") == 0);
  CHECK(text_height("A") == 7);
  CHECK(text_height("A\nB", 3) == 45);

  image<rgb> c(13, 9);
  const auto box = perch::support::draw_text(c.view(), 1, 1, "T1", ink);
  CHECK(art(c) == picture(R"(
    .............
    .#####...#...
    ...#....##...
    ...#.....#...
    ...#.....#...
    ...#.....#...
    ...#.....#...
    ...#....###..
    .............
  )"));
  CHECK(box.x == -1);
  CHECK(box.width == 15);

  image<rgb> s(12, 16);
  perch::support::draw_text(s.view(), 0, 0, "!", ink, {.scale = 2});
  CHECK(s(4, 0) == ink);
  CHECK(s(5, 1) == ink);
  CHECK(s(4, 10) == rgb{});
  CHECK(s(4, 12) == ink);
  CHECK(count_lit(s) == 6 * 4);

  image<rgb> b(20, 12);
  const auto boxed = perch::support::draw_text(
      b.view(), 3, 3, "x", rgb{255, 0, 0},
      {.scale = 1, .alpha = 1.0f, .background = rgb{0, 0, 255}, .background_alpha = 1.0f,
       .padding_px = 2});
  CHECK(boxed.x == 1);
  CHECK(boxed.y == 1);
  CHECK(boxed.width == 9);
  CHECK(boxed.height == 11);
  CHECK(b(1, 1) == rgb{0, 0, 255});
  CHECK(b(9, 11) == rgb{0, 0, 255});
  CHECK(b(10, 11) == rgb{});
  CHECK(b(0, 0) == rgb{});
  CHECK(b(3, 5) == rgb{255, 0, 0});  // 'x' row 2 starts with a dot in column 0
}

TEST_CASE("draw_legend: a box with one row per entry") {
  using perch::support::legend_entry;
  using perch::support::legend_marker;
  const std::array<legend_entry, 3> entries{{
      {"skeleton: diameter", colours::white, legend_marker::ramp},
      {"window passed", colours::green, legend_marker::line},
      {"perch", colours::red, legend_marker::outline},
  }};
  const auto size = perch::support::legend_size(std::span(entries));
  CHECK(size.width == 4 + 14 + 4 + perch::support::text_width("skeleton: diameter") + 4);
  CHECK(size.height == 4 + 3 * 11 - 3 + 4);
  image<rgb> c(200, 60);
  const auto box = perch::support::draw_legend(
      c.view(), 5, 6, std::span(entries),
      {.scale = 1, .text = colours::white, .background = rgb{0, 0, 50}, .background_alpha = 1.0f});
  CHECK(box.x == 5);
  CHECK(box.width == size.width);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 200; ++x) {
      const bool inside = x >= box.x && x < box.x + box.width && y >= box.y &&
                          y < box.y + box.height;
      if (!inside) CHECK(c(x, y) == rgb{});
      if (inside) CHECK_FALSE(c(x, y) == rgb{});
    }
  CHECK(c(9, 10) == perch::support::colour_map(0.0f));   // ramp starts at the marker's left
  CHECK(c(9 + 13, 10) == perch::support::colour_map(1.0f));
  CHECK(c(9, 6 + 4 + 11 + 2) == colours::green);         // line marker on row 2
  CHECK(perch::support::legend_size({}).width == 0);
}
