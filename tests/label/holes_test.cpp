// SPDX-License-Identifier: BSL-1.0
#include "perch/label/holes.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "allocation_counter.hpp"
#include "perch/core/image.hpp"
#include "perch/label/topology.hpp"
#include "support/ascii_art.hpp"

using perch::errc;
using perch::image;
using perch::image_view;
using perch::workspace;
using perch::support::mask_from_ascii;
using perch::support::to_ascii;

namespace {

struct reference_fill {
  int holes = 0;  // all of them, small or not
  int filled = 0;
  long long filled_pixels = 0;
};

// Reference: 4-connected flood fills of the background; a region that reaches the border is
// outside, every other region is a hole, filled when it has at most `max_area` pixels.
template <perch::MutableImageView Mask>
reference_fill fill_by_flood(const Mask& mask, long long max_area) {
  const int w = mask.width();
  const int h = mask.height();
  std::vector<char> seen(static_cast<std::size_t>(w * h), 0);
  reference_fill out;
  for (int sy = 0; sy < h; ++sy)
    for (int sx = 0; sx < w; ++sx) {
      if (mask(sx, sy) != 0 || seen[static_cast<std::size_t>(sy * w + sx)] != 0) continue;
      std::vector<std::pair<int, int>> stack{{sx, sy}}, region;
      seen[static_cast<std::size_t>(sy * w + sx)] = 1;
      bool outside = false;
      while (!stack.empty()) {
        const auto [x, y] = stack.back();
        stack.pop_back();
        region.emplace_back(x, y);
        outside = outside || x == 0 || y == 0 || x == w - 1 || y == h - 1;
        for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
          const int nx = x + dx, ny = y + dy;
          if (nx < 0 || ny < 0 || nx >= w || ny >= h || mask(nx, ny) != 0) continue;
          if (seen[static_cast<std::size_t>(ny * w + nx)] != 0) continue;
          seen[static_cast<std::size_t>(ny * w + nx)] = 1;
          stack.emplace_back(nx, ny);
        }
      }
      if (outside) continue;
      ++out.holes;
      if (static_cast<long long>(region.size()) > max_area) continue;
      ++out.filled;
      out.filled_pixels += static_cast<long long>(region.size());
      for (const auto& [x, y] : region) mask(x, y) = 1;
    }
  return out;
}

// The runs, listed afresh, must equal the runs fill_small_holes left behind.
void check_runs(const perch::row_runs& joined, image_view<const std::uint8_t> mask) {
  workspace ws;
  auto fresh = perch::find_row_runs(
      mask, ws, static_cast<std::size_t>(mask.width()) * static_cast<std::size_t>(mask.height()));
  REQUIRE(fresh);
  REQUIRE(joined.size() == fresh->size());
  for (int y = 0; y < mask.height(); ++y) {
    const auto a = joined.row(y);
    const auto b = fresh->row(y);
    REQUIRE(a.size() == b.size());
    for (std::size_t k = 0; k < a.size(); ++k) {
      CHECK(a[k].begin == b[k].begin);
      CHECK(a[k].end == b[k].end);
    }
  }
}

// Fills `art`'s holes of at most `max_area` pixels; checks the result against the reference.
std::string filled(std::string_view art, long long max_area,
                   perch::hole_fill_report* report = nullptr) {
  auto mask = mask_from_ascii(art);
  auto expected = mask_from_ascii(art);
  const reference_fill want = fill_by_flood(expected.view(), max_area);
  workspace ws;
  auto runs = perch::find_row_runs(image_view<const std::uint8_t>(mask.view()), ws, 1000);
  REQUIRE(runs);
  auto got = perch::fill_small_holes(mask.view(), *runs, max_area, ws);
  REQUIRE(got);
  CHECK(got->filled == want.filled);
  CHECK(got->filled_pixels == want.filled_pixels);
  CHECK(to_ascii(mask.view()) == to_ascii(expected.view()));
  check_runs(*runs, mask.view());
  if (report != nullptr) *report = *got;
  return to_ascii(mask.view());
}

}  // namespace

// A branch with a one-pixel pinhole and a 2 × 3 hole.
constexpr std::string_view branch_with_holes = R"(
    ..........
    ##########
    ##.###...#
    ######...#
    ##########
    ..........)";
constexpr std::string_view branch_pinhole_filled = R"(
    ..........
    ##########
    ######...#
    ######...#
    ##########
    ..........)";
// A hole winding over three rows: 7 pixels, one hole.
constexpr std::string_view s_hole = R"(
    ######
    #...##
    ###.##
    ##...#
    ######)";
// A ring inside a hole: a 1-pixel hole in the ring, a 16-pixel one round it.
constexpr std::string_view nested = R"(
    #######
    #.....#
    #.###.#
    #.#.#.#
    #.###.#
    #.....#
    #######)";

TEST_CASE("fill_small_holes: pinholes go, larger holes and open bays stay") {
  perch::hole_fill_report r;
  // Only the pinhole goes at max 4.
  CHECK(filled(branch_with_holes, 4, &r) ==
        to_ascii(mask_from_ascii(branch_pinhole_filled).view()));
  CHECK(r.filled == 1);
  CHECK(r.filled_pixels == 1);
  // With room for six pixels both go; with 0 none does.
  (void)filled("#####\n#.#.#\n#####", 6, &r);
  CHECK(r.filled == 2);
  (void)filled("#####\n#.#.#\n#####", 0, &r);
  CHECK(r.filled == 0);
  // A bay open to the border is no hole, however small.
  (void)filled("###\n#.#\n#.#", 10, &r);
  CHECK(r.filled == 0);
  // An 8-connected diamond encloses its middle (4-connected background): a hole.
  (void)filled(".#.\n#.#\n.#.", 1, &r);
  CHECK(r.filled == 1);
  // Two pockets that touch only diagonally are two holes of one pixel each.
  (void)filled("####\n#.##\n##.#\n####", 1, &r);
  CHECK(r.filled == 2);
  // The winding hole is measured whole.
  (void)filled(s_hole, 6, &r);
  CHECK(r.filled == 0);
  (void)filled(s_hole, 7, &r);
  CHECK(r.filled == 1);
  // Nested: the hole round the ring is not small at 1; at 16 both go, the ring joins the rim.
  (void)filled(nested, 1, &r);
  CHECK(r.filled == 1);
  (void)filled(nested, 16, &r);
  CHECK(r.filled == 2);
  CHECK(r.filled_pixels == 17);
  // No foreground, no holes; an all-foreground mask, no holes.
  (void)filled("...\n...", 5, &r);
  CHECK(r.filled == 0);
  (void)filled("###\n###", 5, &r);
  CHECK(r.filled == 0);
}

TEST_CASE("fill_small_holes: agrees with flood fill on random masks, and keeps the topology") {
  std::mt19937 rng(77);
  std::uniform_int_distribution<int> size(1, 40);
  std::uniform_real_distribution<double> density(0.3, 0.95);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  std::uniform_int_distribution<int> area(0, 12);
  std::uniform_int_distribution<int> large_area(13, 600);
  int mismatches = 0;
  for (int trial = 0; trial < 1500; ++trial) {
    const int w = size(rng);
    const int h = size(rng);
    const double p = density(rng);
    const long long max_area = trial % 3 == 0 ? large_area(rng) : area(rng);
    // A strided sub-view of a larger buffer, its surround of the other value.
    image<std::uint8_t> big(w + 3, h + 2, static_cast<std::uint8_t>(trial % 2));
    const auto mask = big.view().sub_view(2, 1, w, h);
    image<std::uint8_t> expected(w, h, 0);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) expected(x, y) = mask(x, y) = coin(rng) < p ? 1 : 0;
    const reference_fill want = fill_by_flood(expected.view(), max_area);
    workspace ws;
    auto before = perch::count_topology(image_view<const std::uint8_t>(mask), ws);
    auto runs = perch::find_row_runs(image_view<const std::uint8_t>(mask), ws,
                                     static_cast<std::size_t>(w * h));
    REQUIRE(before);
    REQUIRE(runs);
    auto got = perch::fill_small_holes(mask, *runs, max_area, ws);
    REQUIRE(got);
    auto after = perch::count_topology(image_view<const std::uint8_t>(mask), ws);
    REQUIRE(after);
    const bool same = got->filled == want.filled && got->filled_pixels == want.filled_pixels &&
                      to_ascii(mask) == to_ascii(expected.view()) &&
                      after->holes == before->holes - got->filled &&
                      after->components <= before->components;  // islands in a hole join
    if (!same && ++mismatches <= 3) {
      INFO("max_area " << max_area << "\n"
                       << to_ascii(expected.view()) << "perch\n"
                       << to_ascii(mask));
      CHECK(false);
    }
    check_runs(*runs, image_view<const std::uint8_t>(mask));
  }
  CHECK(mismatches == 0);
}

TEST_CASE("fill_small_holes: exact workspace, no allocation, bad input") {
  auto mask = mask_from_ascii("#####\n#.#.#\n#####\n#...#\n#####");
  workspace lists;
  auto runs = perch::find_row_runs(image_view<const std::uint8_t>(mask.view()), lists, 100);
  REQUIRE(runs);
  const std::size_t bytes = perch::fill_holes_workspace_bytes(mask.height(), runs->size());
  std::vector<std::byte> buffer(bytes + workspace::alignment);
  const auto skip = (workspace::alignment -
                     reinterpret_cast<std::uintptr_t>(buffer.data()) % workspace::alignment) %
                    workspace::alignment;
  {
    workspace small{std::span<std::byte>(buffer.data() + skip, bytes - workspace::alignment)};
    auto got = perch::fill_small_holes(mask.view(), *runs, 2, small);
    REQUIRE(!got);
    CHECK(got.error().code == errc::workspace_too_small);
    CHECK(small.used() == 0);
    CHECK(to_ascii(mask.view()) == "#####\n#.#.#\n#####\n#...#\n#####\n");
  }
  {
    workspace exact{std::span<std::byte>(buffer.data() + skip, bytes)};
    perch::test::allocation_scope scope;
    auto got = perch::fill_small_holes(mask.view(), *runs, 2, exact);
    CHECK(scope.count() == 0);
    REQUIRE(got);
    CHECK(got->filled == 2);
    CHECK(exact.used() == 0);
    CHECK(exact.high_water() == bytes);
  }
  workspace ws;
  auto other = mask_from_ascii("###\n#.#\n###");
  auto wrong = perch::fill_small_holes(other.view(), *runs, 2, ws);
  REQUIRE(!wrong);
  CHECK(wrong.error().code == errc::invalid_parameter);
  auto negative = perch::fill_small_holes(mask.view(), *runs, -1, ws);
  REQUIRE(!negative);
  CHECK(negative.error().code == errc::invalid_parameter);
}
