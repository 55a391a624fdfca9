// SPDX-License-Identifier: BSL-1.0
#include "perch/core/mask.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <limits>
#include <utility>
#include <random>
#include <vector>

#include "perch/core/image.hpp"
#include "support/ascii_art.hpp"

using perch::errc;
using perch::image_view;

TEST_CASE("tree_bounds: box of the non-zero pixels, empty for an empty mask") {
  const auto mask = perch::support::mask_from_ascii(R"(
    ......
    ..#...
    ....#.
    ......
  )");
  const perch::pixel_box box = perch::tree_bounds(mask.view());
  CHECK(box.x_min == 2);
  CHECK(box.x_max == 4);
  CHECK(box.y_min == 1);
  CHECK(box.y_max == 2);
  CHECK(box.width() == 3);
  perch::image<std::uint8_t> empty(4, 3);
  CHECK(perch::tree_bounds(empty.view()).empty());
}

TEST_CASE("prepare_mask: crops to the tree with a background border, binarised") {
  perch::image<std::uint8_t> mask(8, 6);
  mask(3, 2) = 200;
  mask(5, 4) = 7;
  perch::workspace ws;
  auto prepared = perch::prepare_mask(mask.view(), ws);
  REQUIRE(prepared);
  const auto& p = prepared->pixels;
  CHECK(p.width() == 3 + 2);
  CHECK(p.height() == 3 + 2);
  CHECK(prepared->offset == perch::pixel{2, 1});
  CHECK(prepared->tree_pixels == 2);
  CHECK(p(1, 1) == 1);
  CHECK(p(3, 3) == 1);
  for (int x = 0; x < p.width(); ++x) CHECK((p(x, 0) == 0 && p(x, p.height() - 1) == 0));
  for (int y = 0; y < p.height(); ++y) CHECK((p(0, y) == 0 && p(p.width() - 1, y) == 0));
}

TEST_CASE("prepare_mask: every tree pixel lands at local + offset") {
  std::mt19937 rng(7);
  perch::workspace ws;
  for (int trial = 0; trial < 200; ++trial) {
    const int w = 1 + static_cast<int>(rng() % 40);
    const int h = 1 + static_cast<int>(rng() % 40);
    // A strided view over a wider buffer.
    const int stride = w + static_cast<int>(rng() % 5);
    std::vector<std::uint8_t> buffer(static_cast<std::size_t>(stride * h), 0);
    for (auto& v : buffer) v = (rng() % 7 == 0) ? 255 : 0;
    image_view<const std::uint8_t> mask(buffer.data(), w, h, stride);
    ws.reset();
    auto prepared = perch::prepare_mask(mask, ws);
    REQUIRE(prepared);
    std::int64_t count = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const int lx = x - prepared->offset.x;
        const int ly = y - prepared->offset.y;
        const bool tree = mask(x, y) != 0;
        count += tree ? 1 : 0;
        if (tree) {
          REQUIRE(prepared->pixels.contains(lx, ly));
          CHECK(prepared->pixels(lx, ly) == 1);
        } else if (prepared->pixels.contains(lx, ly)) {
          CHECK(prepared->pixels(lx, ly) == 0);
        }
      }
    CHECK(prepared->tree_pixels == count);
  }
}

TEST_CASE("prepare_mask: the runs listed while copying are the copy's runs") {
  // find_perch asks for the runs of the copy (runs_listing::list): they must describe the copy
  // and equal a scan of it; when the copy has more runs than detail::max_runs allows, none are
  // listed, the workspace keeps only the copy, and the copy is the same.
  std::mt19937 rng(11);
  perch::workspace ws;
  int listed = 0, too_many = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const int w = 1 + static_cast<int>(rng() % 60);
    const int h = 1 + static_cast<int>(rng() % 40);
    const int stride = w + static_cast<int>(rng() % 5);
    std::vector<std::uint8_t> buffer(static_cast<std::size_t>(stride * h), 0);
    const unsigned sparse = trial % 3 == 0 ? 2 : 5 + static_cast<unsigned>(rng() % 20);
    for (auto& v : buffer) v = rng() % sparse == 0 ? static_cast<std::uint8_t>(1 + rng() % 255) : 0;
    image_view<const std::uint8_t> mask(buffer.data(), w, h, stride);
    ws.reset();
    auto plain = perch::prepare_mask(mask, ws);
    REQUIRE(plain);
    const std::size_t copy_bytes = ws.used();
    auto prepared = perch::prepare_mask(mask, ws, 1.0f, {.runs = perch::runs_listing::list});
    REQUIRE(prepared);
    const perch::row_runs& listed_runs = prepared->runs;
    CHECK(plain->runs.size() == 0);  // listed only when asked for
    const std::size_t listing_bytes = ws.used() - copy_bytes;
    const auto copy = image_view<const std::uint8_t>(prepared->pixels);
    REQUIRE(copy.width() == plain->pixels.width());
    REQUIRE(copy.height() == plain->pixels.height());
    for (int y = 0; y < copy.height(); ++y)
      for (int x = 0; x < copy.width(); ++x) REQUIRE(copy(x, y) == plain->pixels(x, y));
    CHECK(prepared->tree_pixels == plain->tree_pixels);
    CHECK(prepared->offset == plain->offset);
    if (prepared->tree_pixels == 0) {  // an empty mask: nothing to list (find_perch stops)
      CHECK(listed_runs.size() == 0);
      continue;
    }
    const std::size_t limit = perch::detail::max_runs(copy.width(), copy.height());
    auto scanned = perch::find_row_runs(copy, ws, limit);
    if (!scanned) {
      REQUIRE(scanned.error().code == errc::capacity_exceeded);
      CHECK(listed_runs.size() == 0);
      CHECK(!listed_runs.describes(copy));
      CHECK(listing_bytes == copy_bytes);  // the list's memory was given back
      ++too_many;
      continue;
    }
    REQUIRE(listed_runs.describes(copy));
    REQUIRE(listed_runs.size() == scanned->size());
    for (int y = 0; y < copy.height(); ++y) {
      const auto a = listed_runs.row(y);
      const auto b = scanned->row(y);
      REQUIRE(a.size() == b.size());
      for (std::size_t k = 0; k < a.size(); ++k) {
        CHECK(a[k].begin == b[k].begin);
        CHECK(a[k].end == b[k].end);
      }
    }
    ++listed;
  }
  MESSAGE(listed << " copies listed, " << too_many << " with too many runs");
  CHECK(listed >= 100);
  CHECK(too_many >= 20);
}

TEST_CASE("prepare_mask: a box larger than max_box_pixels is refused before it takes memory") {
  perch::image<std::uint8_t> mask(40, 30);
  for (int y = 5; y < 15; ++y)
    for (int x = 10; x < 30; ++x) mask(x, y) = 1;
  const std::size_t box = 22 * 12;  // 20 × 10 and the border
  perch::workspace ws;
  auto fits = perch::prepare_mask(mask.view(), ws, 1.0f, {.max_box_pixels = box});
  REQUIRE(fits);
  CHECK(static_cast<std::size_t>(fits->pixels.width() * fits->pixels.height()) == box);
  ws.reset();
  auto refused = perch::prepare_mask(mask.view(), ws, 1.0f, {.max_box_pixels = box - 1});
  REQUIRE_FALSE(refused);
  CHECK(refused.error().code == errc::capacity_exceeded);
  CHECK(refused.error().detail == "prepare_options.max_box_pixels");
  CHECK(refused.error().needed == box);
  CHECK(ws.used() == 0);
}

TEST_CASE("prepare_mask: an empty mask is not an error") {
  perch::image<std::uint8_t> mask(5, 5);
  perch::workspace ws;
  auto prepared = perch::prepare_mask(mask.view(), ws);
  REQUIRE(prepared);
  CHECK(prepared->tree_pixels == 0);
}

TEST_CASE("prepare_mask: area downscale keeps a strip's width in proportion") {
  // A horizontal strip 8 px tall, aligned to the grids: at 0.5 → 4 px; at 0.25 → 2 px.
  perch::image<std::uint8_t> mask(64, 40);
  for (int y = 8; y < 16; ++y)
    for (int x = 0; x < 64; ++x) mask(x, y) = 1;
  perch::workspace ws;
  for (const auto& [factor, rows] : {std::pair{0.5f, 4}, std::pair{0.25f, 2}}) {
    ws.reset();
    auto prepared = perch::prepare_mask(mask.view(), ws, factor);
    REQUIRE(prepared);
    CHECK(prepared->analysed_width == static_cast<int>(64 * factor));
    CHECK(prepared->tree_pixels == static_cast<std::int64_t>(rows) * static_cast<int>(64 * factor));
    // The strip's centre maps back to the input's.
    const auto& p = prepared->pixels;
    float sum = 0;
    int n = 0;
    for (int y = 0; y < p.height(); ++y)
      if (p(2, y) != 0) {
        sum += static_cast<float>(y + prepared->offset.y);
        ++n;
      }
    REQUIRE(n > 0);
    const perch::point2f centre = prepared->to_input({10.0f, sum / static_cast<float>(n)});
    CHECK(centre.y() == doctest::Approx(11.5).epsilon(0.02));
    // Asked for, the runs of the reduced copy: one per row of the strip.
    auto listed = perch::prepare_mask(mask.view(), ws, factor, {.runs = perch::runs_listing::list});
    REQUIRE(listed);
    CHECK(listed->runs.describes(image_view<const std::uint8_t>(listed->pixels)));
    CHECK(listed->runs.size() == static_cast<std::size_t>(rows));
  }
}

TEST_CASE("prepare_mask: bad input gets a status") {
  perch::workspace ws;
  image_view<const std::uint8_t> null_view(nullptr, 4, 4);
  CHECK(perch::prepare_mask(null_view, ws).error().code == errc::null_data);
  perch::image<std::uint8_t> mask(4, 4);
  CHECK(perch::prepare_mask(mask.view(), ws, 0.0f).error().code == errc::invalid_parameter);
  CHECK(perch::prepare_mask(mask.view(), ws, 1.5f).error().code == errc::invalid_parameter);
  CHECK(perch::prepare_mask(mask.view(), ws, std::numeric_limits<float>::quiet_NaN()).error().code ==
        errc::invalid_parameter);
  image_view<const std::uint8_t> empty(mask.data(), 0, 4);
  CHECK(perch::prepare_mask(empty, ws).error().code == errc::empty_image);
}
