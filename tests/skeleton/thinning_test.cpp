// SPDX-License-Identifier: BSL-1.0
#include "perch/skeleton/thinning.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "perch/core/image.hpp"
#include "perch/distance/distance_transform.hpp"
#include "support/ascii_art.hpp"

using perch::image;
using perch::image_view;
using perch::thinness;
using perch::workspace;
using perch::support::mask_from_ascii;
using perch::support::to_ascii;

namespace {

enum class method { zhang_suen, guo_hall };

// The papers' whole-image sweeps, written from the conditions with the papers' own names.
image<std::uint8_t> reference_thinning(const image<std::uint8_t>& mask, method m) {
  const int w = mask.width();
  const int h = mask.height();
  auto at = [&](const image<std::uint8_t>& img, int x, int y) -> int {
    return img.view().contains(x, y) && img(x, y) != 0 ? 1 : 0;
  };
  image<std::uint8_t> img(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) img(x, y) = mask(x, y) != 0 ? 1 : 0;
  bool changed = true;
  while (changed) {
    changed = false;
    for (int sub = 0; sub < 2; ++sub) {
      std::vector<std::pair<int, int>> remove;
      for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
          if (img(x, y) == 0) continue;
          const int n = at(img, x, y - 1), ne = at(img, x + 1, y - 1), e = at(img, x + 1, y),
                    se = at(img, x + 1, y + 1), s = at(img, x, y + 1), sw = at(img, x - 1, y + 1),
                    wv = at(img, x - 1, y), nw = at(img, x - 1, y - 1);
          bool del = false;
          if (m == method::zhang_suen) {
            const int p[10] = {0, 0, n, ne, e, se, s, sw, wv, nw};
            const int b = n + ne + e + se + s + sw + wv + nw;
            int a = 0;
            for (int k = 2; k <= 9; ++k) a += (p[k] == 0 && p[k == 9 ? 2 : k + 1] == 1) ? 1 : 0;
            const bool c = sub == 0 ? (p[2] * p[4] * p[6] == 0 && p[4] * p[6] * p[8] == 0)
                                    : (p[2] * p[4] * p[8] == 0 && p[2] * p[6] * p[8] == 0);
            del = b >= 2 && b <= 6 && a == 1 && c;
          } else {
            const int x1 = e, x2 = ne, x3 = n, x4 = nw, x5 = wv, x6 = sw, x7 = s, x8 = se;
            const int c = (!x1 && (x2 || x3)) + (!x3 && (x4 || x5)) + (!x5 && (x6 || x7)) +
                          (!x7 && (x8 || x1));
            const int n1 = (x1 || x2) + (x3 || x4) + (x5 || x6) + (x7 || x8);
            const int n2 = (x2 || x3) + (x4 || x5) + (x6 || x7) + (x8 || x1);
            const int nn = std::min(n1, n2);
            const bool cond = sub == 0 ? !((x2 || x3 || !x8) && x1) : !((x6 || x7 || !x4) && x5);
            del = c == 1 && nn >= 2 && nn <= 3 && cond;
          }
          if (del) remove.emplace_back(x, y);
        }
      for (auto [x, y] : remove) img(x, y) = 0;
      if (!remove.empty()) changed = true;
    }
  }
  return img;
}

image<std::uint8_t> random_mask(std::mt19937& rng, int w, int h, bool noise = true) {
  image<std::uint8_t> m(w, h);
  const double density = std::uniform_real_distribution<double>(0.1, 0.95)(rng);
  std::bernoulli_distribution ink(density);
  if (noise && rng() % 3 == 0) {
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) m(x, y) = ink(rng) ? 1 : 0;
    return m;
  }
  // Thick random strokes, with some noise.
  const int strokes = 1 + static_cast<int>(rng() % 4);
  for (int k = 0; k < strokes; ++k) {
    const auto x0 = static_cast<double>(rng() % static_cast<unsigned>(w)), y0 = static_cast<double>(rng() % static_cast<unsigned>(h));
    const auto x1 = static_cast<double>(rng() % static_cast<unsigned>(w)), y1 = static_cast<double>(rng() % static_cast<unsigned>(h));
    const double r = 0.5 + static_cast<double>(rng() % 40) / 10.0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const double dx = x1 - x0, dy = y1 - y0;
        const double len2 = dx * dx + dy * dy;
        double t = len2 > 0 ? ((x - x0) * dx + (y - y0) * dy) / len2 : 0.0;
        t = std::clamp(t, 0.0, 1.0);
        const double ex = x - (x0 + t * dx), ey = y - (y0 + t * dy);
        if (ex * ex + ey * ey <= r * r) m(x, y) = 1;
      }
  }
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      if (noise && ink(rng) && ink(rng) && ink(rng) && rng() % 4 == 0) m(x, y) = 1;
  return m;
}

template <class S>
image<std::uint8_t> run(const S& s, const image<std::uint8_t>& mask, workspace& ws) {
  image<std::uint32_t> d2(mask.width(), mask.height());
  REQUIRE(perch::distance_transform_sq(mask.view(), d2.view(), ws));
  image<std::uint8_t> out(mask.width(), mask.height(), 9);
  REQUIRE(s(mask.view(), d2.view(), out.view(), ws));
  return out;
}

bool has_block(const image<std::uint8_t>& s) {
  for (int y = 0; y + 1 < s.height(); ++y)
    for (int x = 0; x + 1 < s.width(); ++x)
      if (s(x, y) && s(x + 1, y) && s(x, y + 1) && s(x + 1, y + 1)) return true;
  return false;
}

bool equal(const image<std::uint8_t>& a, const image<std::uint8_t>& b) {
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x)
      if ((a(x, y) != 0) != (b(x, y) != 0)) return false;
  return true;
}

}  // namespace

TEST_CASE("thinning: faithful Zhang-Suen and Guo-Hall equal the papers' whole-image sweeps") {
  std::mt19937 rng(1984);
  workspace ws;
  int compared = 0;
  for (int round = 0; round < 1500; ++round) {
    const int w = 1 + static_cast<int>(rng() % 40);
    const int h = 1 + static_cast<int>(rng() % 40);
    const auto mask = random_mask(rng, w, h);
    const auto zs = run(perch::zhang_suen{.thinness = thinness::faithful}, mask, ws);
    const auto gh = run(perch::guo_hall{.thinness = thinness::faithful}, mask, ws);
    const bool zs_ok = equal(zs, reference_thinning(mask, method::zhang_suen));
    const bool gh_ok = equal(gh, reference_thinning(mask, method::guo_hall));
    if (!zs_ok || !gh_ok) {
      INFO("mask:\n" << to_ascii(mask.view()) << "zs:\n" << to_ascii(zs.view()) << "gh:\n"
                     << to_ascii(gh.view()));
      CHECK(zs_ok);
      CHECK(gh_ok);
    }
    compared += 2;
  }
  CHECK(compared == 3000);
}

TEST_CASE("thinning: faithful output is a fixed point; one_pixel output has no 2x2 block") {
  std::mt19937 rng(32);
  workspace ws;
  for (int round = 0; round < 400; ++round) {
    // Strokes without noise: a noisy mask can hold a block that no short re-route through the
    // mask removes, or one no thin subset of its topology avoids (see skeletoniser_test).
    const auto mask = random_mask(rng, 5 + static_cast<int>(rng() % 40),
                                  5 + static_cast<int>(rng() % 40), false);
    for (int m = 0; m < 2; ++m) {
      const auto faithful = m == 0 ? run(perch::zhang_suen{.thinness = thinness::faithful}, mask, ws)
                                   : run(perch::guo_hall{.thinness = thinness::faithful}, mask, ws);
      const auto again = m == 0 ? run(perch::zhang_suen{.thinness = thinness::faithful}, faithful, ws)
                                : run(perch::guo_hall{.thinness = thinness::faithful}, faithful, ws);
      CHECK(equal(faithful, again));
      const auto thin = m == 0 ? run(perch::zhang_suen{}, mask, ws) : run(perch::guo_hall{}, mask, ws);
      if (has_block(thin)) {
        INFO(to_ascii(mask.view()) << "\n" << to_ascii(thin.view()));
        CHECK(!has_block(thin));
      }
      for (int y = 0; y < mask.height(); ++y)
        for (int x = 0; x < mask.width(); ++x) {
          REQUIRE(thin(x, y) <= 1);
          REQUIRE((thin(x, y) == 0 || mask(x, y) != 0));
        }
    }
  }
}

TEST_CASE("thinning: the papers' known cases") {
  workspace ws;
  const auto square = mask_from_ascii(R"(
    ##
    ##)");
  // Zhang-Suen erases a 2x2 square; Guo-Hall keeps one pixel of it.
  const auto zs = run(perch::zhang_suen{.thinness = thinness::faithful}, square, ws);
  const auto gh = run(perch::guo_hall{.thinness = thinness::faithful}, square, ws);
  int zs_count = 0, gh_count = 0;
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x) {
      zs_count += zs(x, y);
      gh_count += gh(x, y);
    }
  CHECK(zs_count == 0);
  CHECK(gh_count == 1);
  const auto bar = mask_from_ascii(R"(
    ...........
    .#########.
    .#########.
    .#########.
    ...........)");
  const auto thin = run(perch::zhang_suen{}, bar, ws);
  CHECK(to_ascii(thin.view()) ==
        "...........\n"
        "...........\n"
        "..######...\n"
        "...........\n"
        "...........\n");
}
