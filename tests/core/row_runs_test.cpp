// SPDX-License-Identifier: BSL-1.0
#include "perch/core/row_runs.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "perch/core/image.hpp"

using perch::image;
using perch::image_view;
using perch::row_run;
using perch::workspace;

namespace {

// The runs of one row, one pixel at a time.
std::vector<row_run> naive_runs(image_view<const std::uint8_t> m, int y) {
  std::vector<row_run> out;
  for (int x = 0; x < m.width(); ++x) {
    if (m(x, y) == 0) continue;
    if (out.empty() || out.back().end != x) out.push_back({x, x});
    out.back().end = x + 1;
  }
  return out;
}

}  // namespace

TEST_CASE("find_row_runs: equals a pixel-by-pixel scan on random masks, dense and strided") {
  std::mt19937 rng(31);
  workspace ws;
  int runs_seen = 0;
  for (int round = 0; round < 300; ++round) {
    const int w = 1 + static_cast<int>(rng() % 90);
    const int h = 1 + static_cast<int>(rng() % 20);
    image<std::uint8_t> big(w + 7, h + 2, 0xFF);  // ink around the sub-view must not leak in
    const double density = std::uniform_real_distribution<double>(0.0, 1.0)(rng);
    for (int y = 0; y < h; ++y) {
      int x = 0;
      while (x < w) {  // runs of 1-24 pixels, any non-zero byte as ink
        const int run = 1 + static_cast<int>(rng() % 24);
        const bool ink = std::bernoulli_distribution(density)(rng);
        for (int k = 0; k < run && x < w; ++k, ++x)
          big(x + 3, y + 1) = ink ? static_cast<std::uint8_t>(1 + rng() % 255) : 0;
      }
    }
    const auto m = image_view<const std::uint8_t>(big.view().sub_view(3, 1, w, h));
    ws.reset();
    const auto runs = perch::find_row_runs(m, ws, static_cast<std::size_t>(w * h));
    REQUIRE(runs);
    CHECK(runs->describes(m));
    std::size_t total = 0;
    for (int y = 0; y < h; ++y) {
      const auto expected = naive_runs(m, y);
      const auto got = runs->row(y);
      REQUIRE(got.size() == expected.size());
      for (std::size_t i = 0; i < got.size(); ++i) {
        CHECK(got[i].begin == expected[i].begin);
        CHECK(got[i].end == expected[i].end);
      }
      total += got.size();
    }
    CHECK(runs->size() == total);
    runs_seen += static_cast<int>(total);
  }
  CHECK(runs_seen > 2000);
}

TEST_CASE("row_runs: describe only the view they were found on") {
  workspace ws;
  image<std::uint8_t> a(10, 4, 1);
  image<std::uint8_t> b(10, 4, 1);
  const auto runs = perch::find_row_runs(a.view(), ws, 64);
  REQUIRE(runs);
  CHECK(runs->describes(a.view()));
  CHECK(runs->describes(image_view<const std::uint8_t>(a.view())));
  CHECK_FALSE(runs->describes(b.view()));                  // other pixels
  CHECK_FALSE(runs->describes(a.view().sub_view(0, 0, 9, 4)));  // same start, other size
  CHECK_FALSE(runs->describes(image_view<std::uint8_t>(&a(0, 0), 5, 4, 10)));  // other stride
  CHECK(runs->size() == 4);
  const perch::row_runs none;
  CHECK_FALSE(none.describes(a.view()));
  CHECK(none.size() == 0);
}

TEST_CASE("find_row_runs: too many runs is capacity_exceeded and leaves the workspace as it was") {
  image<std::uint8_t> checker(16, 3);
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 16; ++x) checker(x, y) = (x + y) % 2 == 0;  // 8 runs a row
  workspace ws;
  const std::size_t before = ws.used();
  const auto full = perch::find_row_runs(checker.view(), ws, 23);
  REQUIRE_FALSE(full);
  CHECK(full.error().code == perch::errc::capacity_exceeded);
  CHECK(full.error().needed == 24);
  CHECK(ws.used() == before);
  const auto fits = perch::find_row_runs(checker.view(), ws, 24);
  REQUIRE(fits);
  CHECK(fits->size() == 24);
  CHECK(ws.used() - before <= perch::row_runs_workspace_bytes(3, 24));
  // Bad views are statuses.
  CHECK(perch::find_row_runs(image_view<const std::uint8_t>(nullptr, 4, 4), ws, 8).error().code ==
        perch::errc::null_data);
}

TEST_CASE("for_each_gap and for_each_uncovered: equal a pixel-by-pixel test, ranges in row order") {
  // Three random rows (above, middle, below); the middle row's runs widened by one each way
  // give the ranges the medial axis asks about, as does the run itself less its ends.
  std::mt19937 rng(1127);
  int pixels_checked = 0;
  for (int round = 0; round < 2000; ++round) {
    const int w = 3 + static_cast<int>(rng() % 80);
    const double density = std::uniform_real_distribution<double>(0.05, 0.95)(rng);
    std::bernoulli_distribution ink(density);
    image<std::uint8_t> m(w, 3, 0);
    for (int y = 0; y < 3; ++y)
      for (int x = 1; x + 1 < w; ++x) m(x, y) = ink(rng) ? 1 : 0;
    const image_view<const std::uint8_t> v = m.view();
    const std::vector<row_run> above = naive_runs(v, 0);
    const std::vector<row_run> middle = naive_runs(v, 1);
    const std::vector<row_run> below = naive_runs(v, 2);
    perch::detail::run_cursor gaps{above};
    perch::detail::run_cursor up{above};
    perch::detail::run_cursor down{below};
    std::vector<int> gap_got, gap_want, bare_got, bare_want;
    for (const row_run r : middle) {
      perch::detail::for_each_gap(gaps, r.begin - 1, r.end + 1, [&](int from, int to) {
        REQUIRE(from < to);
        for (int x = from; x < to; ++x) gap_got.push_back(x);
      });
      for (int x = r.begin - 1; x <= r.end; ++x)
        if (m(x, 0) == 0) gap_want.push_back(x);
      perch::detail::for_each_uncovered(up, down, r.begin + 1, r.end - 1,
                                        [&](int x) { bare_got.push_back(x); });
      for (int x = r.begin + 1; x < r.end - 1; ++x)
        if (m(x, 0) == 0 || m(x, 2) == 0) bare_want.push_back(x);
      pixels_checked += r.end - r.begin + 2;
    }
    INFO("round " << round << ", width " << w);
    REQUIRE(gap_got == gap_want);
    REQUIRE(bare_got == bare_want);
  }
  CHECK(pixels_checked > 50000);
}
