// SPDX-License-Identifier: BSL-1.0
#include "perch/core/disc_index.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <span>
#include <tuple>
#include <vector>

#include "perch/core/workspace.hpp"

namespace {

using perch::owned_disc;
using perch::owner_set;
using perch::point2f;

/// The smallest |p − c| − r over the discs not owned by `excluded`, at most `cap`: the
/// definition, over every disc.
float brute_force(const std::vector<owned_disc>& discs, point2f p, const owner_set& excluded,
                  float cap) {
  float best = cap;
  for (const owned_disc& d : discs) {
    if (excluded.contains(d.owner)) continue;
    const float ex = d.x - p.x();
    const float ey = d.y - p.y();
    best = std::min(best, std::sqrt(ex * ex + ey * ey) - d.radius);
  }
  return best;
}

float uniform(std::mt19937& rng, float lo, float hi) {
  return std::uniform_real_distribution<float>(lo, hi)(rng);
}

}  // namespace

TEST_CASE("disc_index: owner sets leave out only their own non-negative ids") {
  const owner_set none;
  CHECK(!none.contains(-1));  // the empty slots never match an unowned disc
  CHECK(!none.contains(0));
  const owner_set some{{4, 0, -1}};
  CHECK(some.contains(4));
  CHECK(some.contains(0));
  CHECK(!some.contains(-1));
  CHECK(!some.contains(-2));  // `unowned_disc`: an obstacle to every limb
  CHECK(!some.contains(5));
  const owner_set three{{7, 8, 9}};
  CHECK(three.contains(9));
  CHECK(!three.contains(10));
}

TEST_CASE("disc_index: surface distance equals a brute-force minimum on random discs") {
  // Frames of every shape, cells from 1 px to larger than the frame, discs inside and outside
  // the frame (clamped to the border cells, measured exactly), queries inside and outside it.
  std::mt19937 rng(24);
  for (int round = 0; round < 300; ++round) {
    const int width = 1 + static_cast<int>(rng() % 300);
    const int height = 1 + static_cast<int>(rng() % 300);
    const int cells[] = {1, 3, 7, 16, 33, 64, 500};
    const int cell = cells[rng() % 7];
    const std::size_t count = rng() % 80;
    const float margin = 60.0f;  // how far outside the frame discs and queries may lie
    std::vector<owned_disc> discs(count);
    const float radius_max = round % 3 == 0 ? 2.0f : 25.0f;
    for (owned_disc& d : discs) {
      d.x = uniform(rng, -margin, static_cast<float>(width) + margin);
      d.y = uniform(rng, -margin, static_cast<float>(height) + margin);
      // Mostly inside the frame: the index's cells matter there.
      if (rng() % 3 != 0) {
        d.x = uniform(rng, 0.0f, static_cast<float>(width) - 0.001f);
        d.y = uniform(rng, 0.0f, static_cast<float>(height) - 0.001f);
      }
      d.radius = rng() % 5 == 0 ? 0.0f : uniform(rng, 0.0f, radius_max);
      d.owner = static_cast<std::int32_t>(rng() % 7) - 2;  // -2 … 4
    }
    perch::workspace ws;
    auto index = perch::disc_index::build(discs, width, height, ws, cell);
    REQUIRE(index);
    REQUIRE(index->size() == count);
    // Every disc is kept, once, as given.
    std::vector<owned_disc> kept(index->discs().begin(), index->discs().end());
    auto key = [](const owned_disc& d) { return std::tuple(d.x, d.y, d.radius, d.owner); };
    auto less = [&](const owned_disc& a, const owned_disc& b) { return key(a) < key(b); };
    std::vector<owned_disc> given = discs;
    std::sort(kept.begin(), kept.end(), less);
    std::sort(given.begin(), given.end(), less);
    for (std::size_t i = 0; i < count; ++i) REQUIRE(key(kept[i]) == key(given[i]));

    for (int q = 0; q < 60; ++q) {
      point2f p(uniform(rng, -margin, static_cast<float>(width) + margin),
                uniform(rng, -margin, static_cast<float>(height) + margin));
      if (q % 2 == 0)
        p = point2f(uniform(rng, 0.0f, static_cast<float>(width)),
                    uniform(rng, 0.0f, static_cast<float>(height)));
      owner_set excluded;
      const int leave_out = static_cast<int>(rng() % 4);
      for (int k = 0; k < leave_out; ++k) excluded.ids[k] = static_cast<std::int32_t>(rng() % 6) - 1;
      const float caps[] = {0.5f, 5.0f, 20.0f, 80.0f, 1000.0f};
      const float cap = caps[rng() % 5];
      const float expected = brute_force(discs, p, excluded, cap);
      const float got = index->surface_distance(p, excluded, cap);
      CAPTURE(round);
      CAPTURE(q);
      CAPTURE(width);
      CAPTURE(height);
      CAPTURE(cell);
      CAPTURE(p.x());
      CAPTURE(p.y());
      CAPTURE(cap);
      REQUIRE(got == doctest::Approx(expected).epsilon(1e-5).scale(1.0));
      REQUIRE(got <= cap);
    }
  }
}

TEST_CASE("disc_index: discs outside the frame are measured from where they are") {
  // A 100 × 100 frame in 16 px cells; a disc far left of it, one far below, one beyond a corner.
  const std::vector<owned_disc> discs{{-200.0f, 50.0f, 10.0f, 0},
                                      {50.0f, 400.0f, 5.0f, 1},
                                      {150.0f, -50.0f, 0.0f, 2}};
  perch::workspace ws;
  auto index = perch::disc_index::build(discs, 100, 100, ws);
  REQUIRE(index);
  const owner_set none;
  // Inside the frame.
  CHECK(index->surface_distance({0.0f, 50.0f}, none, 1000.0f) ==
        doctest::Approx(std::sqrt(150.0f * 150.0f + 100.0f * 100.0f)));
  CHECK(index->surface_distance({0.0f, 50.0f}, owner_set{{2, -1, -1}}, 1000.0f) ==
        doctest::Approx(190.0f));
  CHECK(index->surface_distance({50.0f, 99.0f}, owner_set{{0, 2, -1}}, 1000.0f) ==
        doctest::Approx(296.0f));
  CHECK(index->surface_distance({99.0f, 0.0f}, none, 1000.0f) ==
        doctest::Approx(std::sqrt(51.0f * 51.0f + 50.0f * 50.0f)));
  // Outside the frame, on the same side as the disc (beyond it, and between it and the frame).
  CHECK(index->surface_distance({-150.0f, 50.0f}, none, 1000.0f) == doctest::Approx(40.0f));
  CHECK(index->surface_distance({-260.0f, 50.0f}, none, 1000.0f) == doctest::Approx(50.0f));
  CHECK(index->surface_distance({50.0f, 500.0f}, none, 1000.0f) == doctest::Approx(95.0f));
  CHECK(index->surface_distance({150.0f, -60.0f}, none, 1000.0f) == doctest::Approx(10.0f));
  // Inside a disc: negative.
  CHECK(index->surface_distance({-205.0f, 50.0f}, none, 1000.0f) == doctest::Approx(-5.0f));
  // The cap: nothing nearer than it.
  CHECK(index->surface_distance({0.0f, 50.0f}, none, 100.0f) == 100.0f);
  // Excluding the nearest disc's owner finds the next.
  const owner_set not_left{{0, -1, -1}};
  CHECK(index->surface_distance({-150.0f, 50.0f}, not_left, 1000.0f) ==
        doctest::Approx(std::min(std::sqrt(200.0f * 200.0f + 350.0f * 350.0f) - 5.0f,
                                 std::sqrt(300.0f * 300.0f + 100.0f * 100.0f))));
}

TEST_CASE("disc_index: a large disc in a far cell is found before a near small one is") {
  // The skip test of a cell subtracts its largest radius: a disc of radius 40 centred 45 px
  // away is 5 px from the point, nearer than a radius-0 disc 10 px away in the point's own cell.
  const std::vector<owned_disc> discs{{10.0f, 20.0f, 0.0f, 0}, {65.0f, 10.0f, 40.0f, 1}};
  perch::workspace ws;
  auto index = perch::disc_index::build(discs, 200, 200, ws, 8);
  REQUIRE(index);
  CHECK(index->surface_distance({20.0f, 10.0f}, owner_set{}, 100.0f) ==
        doctest::Approx(5.0f));  // vs the small one's sqrt(10² + 10²) = 14.1
  CHECK(index->surface_distance({20.0f, 10.0f}, owner_set{{1, -1, -1}}, 100.0f) ==
        doctest::Approx(std::sqrt(200.0f)));
  const std::vector<owned_disc> big_first{{10.0f, 20.0f, 0.0f, 0}, {60.0f, 10.0f, 39.0f, 1}};
  auto second = perch::disc_index::build(big_first, 200, 200, ws, 8);
  REQUIRE(second);
  CHECK(second->surface_distance({20.0f, 10.0f}, owner_set{}, 100.0f) == doctest::Approx(1.0f));
  CHECK(second->surface_distance({20.0f, 10.0f}, owner_set{{1, -1, -1}}, 100.0f) ==
        doctest::Approx(std::sqrt(200.0f)));
}

TEST_CASE("disc_index: an empty index answers the cap") {
  const perch::disc_index unbuilt;
  CHECK(unbuilt.size() == 0);
  CHECK(unbuilt.surface_distance({3.0f, 4.0f}, owner_set{}, 42.0f) == 42.0f);
  perch::workspace ws;
  auto empty = perch::disc_index::build({}, 640, 480, ws);
  REQUIRE(empty);
  CHECK(empty->size() == 0);
  CHECK(empty->surface_distance({3.0f, 4.0f}, owner_set{}, 42.0f) == 42.0f);
  CHECK(empty->surface_distance({-30.0f, 4000.0f}, owner_set{}, 7.0f) == 7.0f);
  // Every disc excluded: the cap too.
  const std::vector<owned_disc> own{{10.0f, 10.0f, 3.0f, 5}};
  auto mine = perch::disc_index::build(own, 64, 64, ws);
  REQUIRE(mine);
  CHECK(mine->surface_distance({12.0f, 10.0f}, owner_set{{5, -1, -1}}, 9.0f) == 9.0f);
  CHECK(mine->surface_distance({12.0f, 10.0f}, owner_set{}, 9.0f) == doctest::Approx(-1.0f));
}

TEST_CASE("disc_index: workspace_bytes is what build takes; a small borrowed buffer fails") {
  std::mt19937 rng(5);
  for (int round = 0; round < 40; ++round) {
    const int width = static_cast<int>(rng() % 700);  // 0 and 1 included: one cell at least
    const int height = static_cast<int>(rng() % 500);
    const int cell = 1 + static_cast<int>(rng() % 40);
    std::vector<owned_disc> discs(rng() % 200);
    for (owned_disc& d : discs) {
      d.x = uniform(rng, -10.0f, static_cast<float>(width) + 10.0f);
      d.y = uniform(rng, -10.0f, static_cast<float>(height) + 10.0f);
      d.radius = uniform(rng, 0.0f, 9.0f);
      d.owner = static_cast<std::int32_t>(rng() % 4);
    }
    const std::size_t bytes = perch::disc_index::workspace_bytes(discs.size(), width, height, cell);
    CAPTURE(round);
    CAPTURE(width);
    CAPTURE(height);
    CAPTURE(cell);
    CAPTURE(discs.size());
    // Exactly enough: build succeeds and uses all of it.
    std::vector<std::byte> buffer(bytes + perch::workspace::alignment);
    {
      perch::workspace exact(std::span<std::byte>(buffer).first(
          bytes + (perch::workspace::alignment -
                   reinterpret_cast<std::uintptr_t>(buffer.data()) % perch::workspace::alignment) %
                      perch::workspace::alignment));
      REQUIRE(exact.capacity() == bytes);
      auto index = perch::disc_index::build(discs, width, height, exact, cell);
      REQUIRE(index);
      CHECK(exact.used() == bytes);
      // It answers like one built in an owning workspace.
      perch::workspace owning;
      REQUIRE(owning.reserve(bytes));  // one block: no skipped tails counted as used
      auto reference = perch::disc_index::build(discs, width, height, owning, cell);
      REQUIRE(reference);
      CHECK(owning.used() == bytes);
      const point2f p(uniform(rng, 0.0f, static_cast<float>(width)),
                      uniform(rng, 0.0f, static_cast<float>(height)));
      CHECK(index->surface_distance(p, owner_set{}, 50.0f) ==
            reference->surface_distance(p, owner_set{}, 50.0f));
    }
    // One alignment unit short: a status, never a crash or a write past the buffer.
    if (bytes >= perch::workspace::alignment) {
      const std::size_t skip =
          (perch::workspace::alignment -
           reinterpret_cast<std::uintptr_t>(buffer.data()) % perch::workspace::alignment) %
          perch::workspace::alignment;
      perch::workspace small(
          std::span<std::byte>(buffer).first(skip + bytes - perch::workspace::alignment));
      auto index = perch::disc_index::build(discs, width, height, small, cell);
      REQUIRE(!index);
      CHECK(index.error().code == perch::errc::workspace_too_small);
    }
  }
  // No buffer at all.
  perch::workspace none(std::span<std::byte>{});
  const std::vector<owned_disc> one{{1.0f, 1.0f, 1.0f, 0}};
  auto index = perch::disc_index::build(one, 10, 10, none);
  REQUIRE(!index);
  CHECK(index.error().code == perch::errc::workspace_too_small);
}
