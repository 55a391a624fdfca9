// SPDX-License-Identifier: BSL-1.0
#include "perch/graph/pixel_kinds.hpp"

#include <doctest/doctest.h>

#include <bit>
#include <cstdint>
#include <string>
#include <string_view>

#include "perch/core/image.hpp"
#include "support/ascii_art.hpp"

using perch::pixel_kind;
using perch::support::mask_from_ascii;

namespace {

// Compile-time: on every neighbourhood that is not part of a 2×2 block, the number of path
// neighbours (m-adjacency) equals the crossing number, so kinds and tracing agree.
constexpr bool path_count_matches_crossing_number() {
  for (unsigned m = 0; m < 256; ++m) {
    const auto mask = static_cast<std::uint8_t>(m);
    if (perch::in_block(mask)) continue;
    if (std::popcount(perch::path_neighbours(mask)) != perch::crossing_number(mask)) return false;
  }
  return true;
}
static_assert(path_count_matches_crossing_number());
static_assert(perch::crossing_number(0) == 0 && perch::crossing_number(0xFF) == 0);
static_assert(perch::classify_neighbourhood(0) == pixel_kind::isolated);
static_assert(perch::classify_neighbourhood(0b0000'0001) == pixel_kind::end);        // E
static_assert(perch::classify_neighbourhood(0b0001'0001) == pixel_kind::body);       // E, W
static_assert(perch::classify_neighbourhood(0b0101'0001) == pixel_kind::junction);   // E, W, S
static_assert(perch::classify_neighbourhood(0b0000'0111) == pixel_kind::junction);   // block
// Staircase corner: NW, W, S, SE (8-neighbour count 4, crossing number 2).
static_assert(perch::classify_neighbourhood(0b1101'1000) == pixel_kind::body);

/// Kinds of every pixel written as a picture: '.' background, 'o' isolated, 'e' end,
/// 'b' body, 'J' junction.
std::string kinds_of(std::string_view art) {
  const auto mask = mask_from_ascii(art);
  perch::image<pixel_kind> kinds(mask.width(), mask.height());
  REQUIRE(perch::classify_skeleton(mask.view(), kinds.view()));
  std::string out;
  for (int y = 0; y < mask.height(); ++y) {
    for (int x = 0; x < mask.width(); ++x) {
      switch (kinds(x, y)) {
        case pixel_kind::background: out += '.'; break;
        case pixel_kind::isolated: out += 'o'; break;
        case pixel_kind::end: out += 'e'; break;
        case pixel_kind::body: out += 'b'; break;
        case pixel_kind::junction: out += 'J'; break;
      }
    }
    out += '\n';
  }
  return out;
}

}  // namespace

TEST_CASE("pixel kinds: a staircase diagonal is body pixels between two ends") {
  CHECK(kinds_of(R"(
    #.....
    ##....
    .##...
    ..##..
    ...##.
    ....##
  )") == "e.....\n"
         "bb....\n"
         ".bb...\n"
         "..bb..\n"
         "...bb.\n"
         "....be\n");
}

TEST_CASE("pixel kinds: a pure diagonal and a straight line") {
  CHECK(kinds_of(R"(
    #...
    .#..
    ..#.
    ...#
  )") == "e...\n.b..\n..b.\n...e\n");
  CHECK(kinds_of("#####") == "ebbbe\n");
}

TEST_CASE("pixel kinds: T, Y, X and + have exactly one junction pixel") {
  CHECK(kinds_of(R"(
    #####
    ..#..
    ..#..
  )") == "ebJbe\n"
         "..b..\n"
         "..e..\n");
  CHECK(kinds_of(R"(
    #...#
    .#.#.
    ..#..
    ..#..
  )") == "e...e\n"
         ".b.b.\n"
         "..J..\n"
         "..e..\n");
  CHECK(kinds_of(R"(
    #...#
    .#.#.
    ..#..
    .#.#.
    #...#
  )") == "e...e\n"
         ".b.b.\n"
         "..J..\n"
         ".b.b.\n"
         "e...e\n");
  CHECK(kinds_of(R"(
    ..#..
    ..#..
    #####
    ..#..
    ..#..
  )") == "..e..\n"
         "..b..\n"
         "ebJbe\n"
         "..b..\n"
         "..e..\n");
}

TEST_CASE("pixel kinds: a 2x2 block is four junction pixels; lone pixels are isolated") {
  CHECK(kinds_of(R"(
    #.....
    .##...
    .##...
    ...#..
    ....#.
  )") == "e.....\n"
         ".JJ...\n"
         ".JJ...\n"
         "...b..\n"
         "....e.\n");
  CHECK(kinds_of("#.#") == "o.o\n");
}

TEST_CASE("pixel kinds: pixels outside the image are background") {
  // The corner pixel has only E and S inside the image: a body pixel of an L.
  CHECK(kinds_of(R"(
    ###
    #..
  )") == "bbe\ne..\n");
}

TEST_CASE("pixel kinds: classify_skeleton reports view errors") {
  perch::image<std::uint8_t> skel(4, 4, 0);
  perch::image<pixel_kind> kinds(3, 4);
  auto r = perch::classify_skeleton(skel.view(), kinds.view());
  REQUIRE(!r);
  CHECK(r.error().code == perch::errc::size_mismatch);
  const perch::image_view<const std::uint8_t> bad(nullptr, 4, 4);
  perch::image<pixel_kind> k4(4, 4);
  auto r2 = perch::classify_skeleton(bad, k4.view());
  REQUIRE(!r2);
  CHECK(r2.error().code == perch::errc::null_data);
}
