// SPDX-License-Identifier: BSL-1.0
#include "perch/label/components.hpp"

#include <doctest/doctest.h>

#include <array>
#include <cstdint>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "allocation_counter.hpp"
#include "perch/core/image.hpp"
#include "perch/label.hpp"
#include "support/ascii_art.hpp"

using perch::component_stats;
using perch::connectivity;
using perch::errc;
using perch::image;
using perch::image_view;
using perch::workspace;
using perch::support::mask_from_ascii;

namespace {

// The obviously-correct reference: breadth-first flood fill from each unlabelled foreground
// pixel in raster order, so labels are numbered like scipy.ndimage.label.
template <perch::ImageView Mask>
int flood_fill_labels(const Mask& mask, connectivity conn, std::vector<std::int32_t>& out) {
  const int w = mask.width();
  const int h = mask.height();
  out.assign(static_cast<std::size_t>(w) * static_cast<std::size_t>(h), 0);
  auto index = [w](int x, int y) {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(w) + static_cast<std::size_t>(x);
  };
  auto in = [&](int x, int y) {
    return x >= 0 && y >= 0 && x < w && y < h && static_cast<bool>(mask(x, y));
  };
  int n = 0;
  std::vector<std::pair<int, int>> queue;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      if (!in(x, y) || out[index(x, y)] != 0) continue;
      ++n;
      queue.assign(1, {x, y});
      out[index(x, y)] = n;
      for (std::size_t head = 0; head < queue.size(); ++head) {
        const auto [cx, cy] = queue[head];
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            if ((dx == 0 && dy == 0) || (conn == connectivity::four && dx != 0 && dy != 0))
              continue;
            if (in(cx + dx, cy + dy) && out[index(cx + dx, cy + dy)] == 0) {
              out[index(cx + dx, cy + dy)] = n;
              queue.push_back({cx + dx, cy + dy});
            }
          }
      }
    }
  return n;
}

std::string picture(const image_view<const std::int32_t>& labels) {
  std::string out;
  for (int y = 0; y < labels.height(); ++y) {
    for (int x = 0; x < labels.width(); ++x) {
      const std::int32_t l = labels(x, y);
      out += l == 0 ? '.' : (l < 10 ? static_cast<char>('0' + l) : '+');
    }
    out += '\n';
  }
  return out;
}

// Labels `mask` with perch and the reference; checks they agree exactly; returns n.
template <perch::BinaryView Mask>
int check_against_reference(const Mask& mask, connectivity conn) {
  image<std::int32_t> labels(mask.width(), mask.height(), -7);
  workspace ws;
  auto n = perch::label_components(mask, labels.view(), ws, conn);
  REQUIRE(n);
  std::vector<std::int32_t> expected;
  const int n_ref = flood_fill_labels(mask, conn, expected);
  CHECK(*n == n_ref);
  bool same = true;
  for (int y = 0; y < mask.height(); ++y)
    for (int x = 0; x < mask.width(); ++x)
      same = same && labels(x, y) == expected[static_cast<std::size_t>(y * mask.width() + x)];
  INFO("perch labels:\n" << picture(labels.view()));
  CHECK(same);
  return *n;
}

int count(std::string_view art, connectivity conn) {
  const auto mask = mask_from_ascii(art);
  return check_against_reference(mask.view(), conn);
}

}  // namespace

TEST_CASE("label_components: numbering follows raster order of first pixels (scipy)") {
  const auto mask = mask_from_ascii(R"(
    ....##
    #.....
    #..#..
    ...##.)");
  image<std::int32_t> labels(mask.width(), mask.height());
  workspace ws;
  auto n = perch::label_components(mask.view(), labels.view(), ws);
  REQUIRE(n);
  CHECK(*n == 3);
  CHECK(picture(labels.view()) ==
        "....11\n"
        "2.....\n"
        "2..3..\n"
        "...33.\n");
}

TEST_CASE("label_components: a later-starting branch that joins keeps the first label") {
  // A V whose arms meet at the bottom: both arms get label 1, the label of its first pixel.
  const auto mask = mask_from_ascii(R"(
    ..#...#
    #..#.#.
    #...#..
    ###....)");
  image<std::int32_t> labels(mask.width(), mask.height());
  workspace ws;
  auto n = perch::label_components(mask.view(), labels.view(), ws);
  REQUIRE(n);
  CHECK(*n == 2);
  CHECK(picture(labels.view()) ==
        "..1...1\n"
        "2..1.1.\n"
        "2...1..\n"
        "222....\n");
  CHECK(count(R"(
    ..#...#
    #..#.#.
    #...#..
    ###....)",
              connectivity::four) == 6);
}

TEST_CASE("label_components: ASCII-art shapes, both connectivities") {
  const connectivity e = connectivity::eight;
  const connectivity f = connectivity::four;
  // One-pixel line, two-pixel line, 2x2 block.
  CHECK(count("#########", e) == 1);
  CHECK(count("##########\n##########", f) == 1);
  CHECK(count("##\n##", f) == 1);
  // A ring.
  constexpr std::string_view ring = R"(
    .#####.
    #.....#
    #.....#
    .#####.)";
  CHECK(count(ring, e) == 1);
  CHECK(count(ring, f) == 4);
  // An X: one component 8-connected, nine single pixels 4-connected.
  constexpr std::string_view cross = R"(
    #...#
    .#.#.
    ..#..
    .#.#.
    #...#)";
  CHECK(count(cross, e) == 1);
  CHECK(count(cross, f) == 9);
  // A Y.
  constexpr std::string_view y_shape = R"(
    #.....#
    .#...#.
    ..#.#..
    ...#...
    ...#...
    ...#...)";
  CHECK(count(y_shape, e) == 1);
  CHECK(count(y_shape, f) == 7);
  // A staircase diagonal (8-connected only through corners).
  constexpr std::string_view stairs = R"(
    ##......
    .##.....
    ..##....
    ....#...
    .....#..
    ......##)";
  CHECK(count(stairs, e) == 1);
  CHECK(count(stairs, f) == 4);
  // An anti-diagonal, whose 8-neighbour is upper-right.
  constexpr std::string_view anti = R"(
    ....#
    ...#.
    ..#..
    .#...
    #....)";
  CHECK(count(anti, e) == 1);
  CHECK(count(anti, f) == 5);
  // A comb whose teeth join only at the bottom right: many merges on one row.
  constexpr std::string_view comb = R"(
    #.#.#.#.#
    #.#.#.#.#
    #########)";
  CHECK(count(comb, e) == 1);
  CHECK(count(comb, f) == 1);
  // A spiral.
  constexpr std::string_view spiral = R"(
    #########
    ........#
    #######.#
    #.....#.#
    #.###.#.#
    #.#...#.#
    #.#####.#
    #.......#
    #########)";
  CHECK(count(spiral, e) == 1);
  CHECK(count(spiral, f) == 1);
}

TEST_CASE("label_components: checkerboard") {
  const std::string_view board = R"(
    #.#.#.
    .#.#.#
    #.#.#.
    .#.#.#
    #.#.#.)";
  CHECK(count(board, connectivity::eight) == 1);
  CHECK(count(board, connectivity::four) == 15);
}

TEST_CASE("label_components: a mask touching every border, all-foreground, all-background") {
  constexpr std::string_view borders = R"(
    ##.#.##
    #.....#
    .......
    #.....#
    ##.#.##)";
  CHECK(count(borders, connectivity::eight) == 6);
  CHECK(count(borders, connectivity::four) == 6);

  image<std::uint8_t> full(13, 7, 1);
  CHECK(check_against_reference(full.view(), connectivity::eight) == 1);
  CHECK(check_against_reference(full.view(), connectivity::four) == 1);
  image<std::uint8_t> none(13, 7, 0);
  CHECK(check_against_reference(none.view(), connectivity::eight) == 0);
}

TEST_CASE("label_components: 1x1, 1xN and Nx1 images") {
  for (const int v : {0, 1}) {
    image<std::uint8_t> one(1, 1, static_cast<std::uint8_t>(v));
    CHECK(check_against_reference(one.view(), connectivity::eight) == v);
    CHECK(check_against_reference(one.view(), connectivity::four) == v);
  }
  CHECK(count("##.#..###.#", connectivity::eight) == 4);
  CHECK(count("#\n#\n.\n#\n.\n.\n#\n#", connectivity::eight) == 3);
  // Longer 1xN rows exercise the eight-pixels-at-a-time background skip.
  image<std::uint8_t> row(37, 1, 0);
  row(0, 0) = row(8, 0) = row(9, 0) = row(24, 0) = row(36, 0) = 1;
  CHECK(check_against_reference(row.view(), connectivity::eight) == 4);
}

TEST_CASE("label_components: agrees with flood fill on thousands of random masks") {
  std::mt19937 rng(20240611);
  std::uniform_int_distribution<int> size(1, 40);
  std::uniform_real_distribution<double> density(0.02, 0.98);
  std::uniform_real_distribution<double> coin(0.0, 1.0);
  workspace ws;
  int mismatches = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    const int w = size(rng);
    const int h = size(rng);
    const double p = density(rng);
    image<std::uint8_t> mask(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        mask(x, y) = static_cast<std::uint8_t>(coin(rng) < p ? 1 + trial % 255 : 0);
    for (connectivity conn : {connectivity::eight, connectivity::four}) {
      image<std::int32_t> labels(w, h, -1);
      ws.reset();
      auto n = perch::label_components(mask.view(), labels.view(), ws, conn);
      REQUIRE(n);
      std::vector<std::int32_t> expected;
      const int n_ref = flood_fill_labels(mask.view(), conn, expected);
      bool same = *n == n_ref;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
          same = same && labels(x, y) == expected[static_cast<std::size_t>(y * w + x)];
      if (!same && ++mismatches <= 3) {
        INFO("trial " << trial << " " << w << "x" << h << " p=" << p << "\n"
                      << perch::support::to_ascii(mask.view()) << "\nperch:\n"
                      << picture(labels.view()));
        CHECK(same);
      }
    }
  }
  CHECK(mismatches == 0);
}

TEST_CASE("label_components: larger random masks with structure (blobs and thin lines)") {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 40; ++trial) {
    const int w = 60 + trial * 7;
    const int h = 50 + trial * 3;
    image<std::uint8_t> mask(w, h, 0);
    std::uniform_int_distribution<int> xs(0, w - 1);
    std::uniform_int_distribution<int> ys(0, h - 1);
    // Random line segments (thin, diagonal, crossing) and squares.
    for (int k = 0; k < 30; ++k) {
      int x = xs(rng);
      int y = ys(rng);
      const int dx = static_cast<int>(rng() % 3) - 1;
      const int dy = static_cast<int>(rng() % 3) - 1;
      for (int s = 0; s < 40 && mask.view().contains(x, y); ++s, x += dx, y += dy) mask(x, y) = 1;
    }
    for (int k = 0; k < 5; ++k) {
      const int x0 = xs(rng);
      const int y0 = ys(rng);
      for (int y = y0; y < std::min(h, y0 + 6); ++y)
        for (int x = x0; x < std::min(w, x0 + 6); ++x) mask(x, y) = 1;
    }
    check_against_reference(mask.view(), connectivity::eight);
    check_against_reference(mask.view(), connectivity::four);
  }
}

TEST_CASE("label_components: strided sub-views give the same labels and leave padding alone") {
  std::mt19937 rng(99);
  std::uniform_int_distribution<int> size(1, 30);
  std::uniform_int_distribution<int> bit(0, 2);
  workspace ws;
  for (int trial = 0; trial < 500; ++trial) {
    const int w = size(rng);
    const int h = size(rng);
    // The mask lives inside a larger buffer whose margin is foreground (must not leak in).
    image<std::uint8_t> big_mask(w + 5, h + 4, 1);
    const auto mask = big_mask.view().sub_view(2, 1, w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) mask(x, y) = bit(rng) == 0 ? 1 : 0;
    image<std::uint8_t> dense(w, h);
    perch::copy(mask, dense.view());
    // Labels into a strided sub-view of a buffer filled with a sentinel.
    image<std::int32_t> big_labels(w + 3, h + 2, 12345);
    const auto labels = big_labels.view().sub_view(1, 1, w, h);
    image<std::int32_t> dense_labels(w, h);
    for (connectivity conn : {connectivity::eight, connectivity::four}) {
      ws.reset();
      auto a = perch::label_components(image_view<const std::uint8_t>(mask), labels, ws, conn);
      auto b = perch::label_components(dense.view(), dense_labels.view(), ws, conn);
      REQUIRE(a);
      REQUIRE(b);
      CHECK(*a == *b);
      bool same = true;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) same = same && labels(x, y) == dense_labels(x, y);
      CHECK(same);
      bool padding_kept = true;
      for (int y = 0; y < h + 2; ++y)
        for (int x = 0; x < w + 3; ++x)
          if (!(x >= 1 && x <= w && y >= 1 && y <= h))
            padding_kept = padding_kept && big_labels(x, y) == 12345;
      CHECK(padding_kept);
    }
  }
}

TEST_CASE("label_components: any pixel type that tests as bool") {
  const auto bytes = mask_from_ascii(R"(
    #..#.
    .#..#
    ....#
    ##...)");
  image<float> floats(bytes.width(), bytes.height());
  image<std::int16_t> shorts(bytes.width(), bytes.height());
  for (int y = 0; y < bytes.height(); ++y)
    for (int x = 0; x < bytes.width(); ++x) {
      floats(x, y) = bytes(x, y) != 0 ? 0.5f : 0.0f;
      shorts(x, y) = bytes(x, y) != 0 ? -3 : 0;
    }
  CHECK(check_against_reference(bytes.view(), connectivity::eight) == 3);
  CHECK(check_against_reference(floats.view(), connectivity::eight) == 3);
  CHECK(check_against_reference(shorts.view(), connectivity::eight) == 3);
}

TEST_CASE("label_components: statistics (area and bounding box) match the labels") {
  std::mt19937 rng(4242);
  std::uniform_int_distribution<int> size(1, 35);
  std::uniform_int_distribution<int> bit(0, 1);
  workspace ws;
  std::vector<component_stats> storage(2000);
  for (int trial = 0; trial < 500; ++trial) {
    const int w = size(rng);
    const int h = size(rng);
    image<std::uint8_t> mask(w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) mask(x, y) = static_cast<std::uint8_t>(bit(rng));
    const connectivity conn = trial % 2 == 0 ? connectivity::eight : connectivity::four;
    image<std::int32_t> labels(w, h);
    perch::bounded_vector<component_stats> stats(storage);
    ws.reset();
    auto n = perch::label_components(mask.view(), labels.view(), stats, ws, conn);
    REQUIRE(n);
    REQUIRE(stats.size() == static_cast<std::size_t>(*n));
    std::vector<component_stats> expected(static_cast<std::size_t>(*n),
                                          component_stats{0, w, h, -1, -1});
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        if (labels(x, y) == 0) continue;
        component_stats& s = expected[static_cast<std::size_t>(labels(x, y) - 1)];
        ++s.area;
        s.x_min = std::min(s.x_min, x);
        s.y_min = std::min(s.y_min, y);
        s.x_max = std::max(s.x_max, x);
        s.y_max = std::max(s.y_max, y);
      }
    bool same = true;
    for (std::size_t i = 0; i < expected.size(); ++i)
      same = same && stats[i].area == expected[i].area && stats[i].x_min == expected[i].x_min &&
             stats[i].y_min == expected[i].y_min && stats[i].x_max == expected[i].x_max &&
             stats[i].y_max == expected[i].y_max;
    CHECK(same);
  }

  const auto mask = mask_from_ascii(R"(
    .##....
    .#...#.
    ##...##)");
  image<std::int32_t> labels(mask.width(), mask.height());
  perch::bounded_vector<component_stats> stats(storage);
  auto n = perch::label_components(mask.view(), labels.view(), stats, ws);
  REQUIRE(n);
  REQUIRE(*n == 2);
  CHECK(stats[0].area == 5);
  CHECK((stats[0].x_min == 0 && stats[0].y_min == 0 && stats[0].x_max == 2 && stats[0].y_max == 2));
  CHECK(stats[1].area == 3);
  CHECK((stats[1].x_min == 5 && stats[1].y_min == 1 && stats[1].x_max == 6 && stats[1].y_max == 2));
}

TEST_CASE("label_components: too many components for the stats is an error, never truncation") {
  const auto mask = mask_from_ascii("#.#.#.#");
  image<std::int32_t> labels(mask.width(), mask.height());
  std::array<component_stats, 3> storage{};
  perch::bounded_vector<component_stats> stats(storage);
  REQUIRE(stats.push_back({}));  // cleared by the call
  workspace ws;
  auto n = perch::label_components(mask.view(), labels.view(), stats, ws);
  REQUIRE(!n);
  CHECK(n.error().code == errc::capacity_exceeded);
  CHECK(n.error().needed == 4);
  CHECK(stats.empty());
  // The labels are still complete.
  CHECK(labels(6, 0) == 4);
  std::array<component_stats, 4> enough{};
  perch::bounded_vector<component_stats> stats4(enough);
  auto m = perch::label_components(mask.view(), labels.view(), stats4, ws);
  REQUIRE(m);
  CHECK(stats4.size() == 4);
}

TEST_CASE("label_components: no allocation after warm-up, workspace released") {
  image<std::uint8_t> mask(300, 200, 0);
  std::mt19937 rng(3);
  for (int k = 0; k < 8000; ++k)
    mask(static_cast<int>(rng() % 300), static_cast<int>(rng() % 200)) = 1;
  image<std::int32_t> labels(300, 200);
  std::vector<component_stats> storage(30000);
  workspace ws;
  REQUIRE(perch::label_components(mask.view(), labels.view(), ws));
  CHECK(ws.used() == 0);
  CHECK(ws.high_water() == perch::label_workspace_bytes(300, 200));
  REQUIRE(perch::label_components(mask.view(), labels.view(), ws, connectivity::four));
  perch::test::allocation_scope scope;
  for (int i = 0; i < 3; ++i) {
    perch::bounded_vector<component_stats> stats(storage);
    REQUIRE(perch::label_components(mask.view(), labels.view(), ws));
    REQUIRE(perch::label_components(mask.view(), labels.view(), stats, ws));
    REQUIRE(perch::label_components(mask.view(), labels.view(), ws, connectivity::four));
  }
  CHECK(scope.count() == 0);
}

TEST_CASE("label_components: label_workspace_bytes is exact for a borrowed buffer") {
  for (auto [w, h] : {std::pair{1, 1}, std::pair{7, 5}, std::pair{64, 48}, std::pair{129, 3}}) {
    for (connectivity conn : {connectivity::eight, connectivity::four}) {
      image<std::uint8_t> mask(w, h, 0);
      for (int y = 0; y < h; y += 2)
        for (int x = 0; x < w; x += 2) mask(x, y) = 1;  // the most components possible
      image<std::int32_t> labels(w, h);
      const std::size_t bytes = perch::label_workspace_bytes(w, h, conn);
      std::vector<std::byte> buffer(bytes + workspace::alignment);
      // Exactly `bytes` past an aligned start.
      auto* raw = buffer.data();
      const auto skip =
          (workspace::alignment - reinterpret_cast<std::uintptr_t>(raw) % workspace::alignment) %
          workspace::alignment;
      {
        workspace exact{std::span<std::byte>(raw + skip, bytes)};
        perch::test::allocation_scope scope;
        auto n = perch::label_components(mask.view(), labels.view(), exact, conn);
        REQUIRE(n);
        CHECK(*n == ((w + 1) / 2) * ((h + 1) / 2));
        CHECK(scope.count() == 0);
      }
      {
        workspace small{std::span<std::byte>(raw + skip, bytes - workspace::alignment)};
        auto n = perch::label_components(mask.view(), labels.view(), small, conn);
        REQUIRE(!n);
        CHECK(n.error().code == errc::workspace_too_small);
        CHECK(n.error().needed == bytes);
      }
    }
  }
  CHECK(perch::label_workspace_bytes(0, 5) == 0);
  CHECK(perch::label_workspace_bytes(4, 4) == workspace::footprint<std::int32_t>(2 * 2 + 1));
  CHECK(perch::label_workspace_bytes(4, 4, connectivity::four) ==
        workspace::footprint<std::int32_t>(4 * 2 + 1));
  static_assert(perch::label_workspace_bytes(10, 10) > 0);  // usable at compile time
}

TEST_CASE("label_components: bad input gives a status") {
  workspace ws;
  image<std::uint8_t> mask(4, 3, 1);
  image<std::int32_t> labels(4, 3);
  // Empty image (0x0 and 0xN).
  {
    image<std::uint8_t> empty;
    image<std::int32_t> empty_labels;
    auto n = perch::label_components(empty.view(), empty_labels.view(), ws);
    REQUIRE(!n);
    CHECK(n.error().code == errc::empty_image);
  }
  // Null data with a non-zero size.
  {
    const image_view<const std::uint8_t> null_mask(nullptr, 4, 3);
    auto n = perch::label_components(null_mask, labels.view(), ws);
    REQUIRE(!n);
    CHECK(n.error().code == errc::null_data);
    const image_view<std::int32_t> null_labels(nullptr, 4, 3);
    auto m = perch::label_components(mask.view(), null_labels, ws);
    REQUIRE(!m);
    CHECK(m.error().code == errc::null_data);
  }
  // Stride smaller than the width.
  {
    const image_view<const std::uint8_t> bad(mask.data(), 4, 3, 2);
    auto n = perch::label_components(bad, labels.view(), ws);
    REQUIRE(!n);
    CHECK(n.error().code == errc::stride_too_small);
  }
  // Negative size.
  {
    const image_view<const std::uint8_t> bad(mask.data(), -4, 3);
    auto n = perch::label_components(bad, labels.view(), ws);
    REQUIRE(!n);
    CHECK(n.error().code == errc::bad_dimensions);
  }
  // Size mismatch.
  {
    image<std::int32_t> other(3, 4);
    auto n = perch::label_components(mask.view(), other.view(), ws);
    REQUIRE(!n);
    CHECK(n.error().code == errc::size_mismatch);
  }
  // A connectivity value outside the enum.
  {
    auto n = perch::label_components(mask.view(), labels.view(), ws, static_cast<connectivity>(7));
    REQUIRE(!n);
    CHECK(n.error().code == errc::invalid_parameter);
  }
  // A borrowed workspace that is too small says how much it needed.
  {
    workspace none{std::span<std::byte>{}};
    auto n = perch::label_components(mask.view(), labels.view(), none);
    REQUIRE(!n);
    CHECK(n.error().code == errc::workspace_too_small);
    CHECK(n.error().needed == perch::label_workspace_bytes(4, 3));
  }
  CHECK(ws.used() == 0);
}
