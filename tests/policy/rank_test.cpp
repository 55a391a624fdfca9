// SPDX-License-Identifier: BSL-1.0
#include "perch/policy/rank.hpp"

#include <doctest/doctest.h>

#include <cstdint>
#include <vector>

#include "allocation_counter.hpp"
#include "perch/core/image.hpp"
#include "perch/policy/constraints.hpp"
#include "perch/policy/scorers.hpp"

namespace {

perch::window_measures window(std::int32_t limb, std::uint32_t first, int x, float slope,
                              float diameter) {
  perch::window_measures m;
  m.limb = limb;
  m.first = first;
  m.centre = {x, 50};
  m.slope_deg = slope;
  m.claw_diameter_mm = diameter;
  m.mm_per_px = 1.0f;
  m.length_px = 20.0f;
  return m;
}

}  // namespace

TEST_CASE("rank: viability, eq. 3 ranking, distinct sites and why the others lost") {
  // A horizontal branch 5 px thick along row 50, with a clump of twigs over x in [70, 90].
  perch::image<std::uint8_t> mask(120, 100, 0);
  for (int x = 0; x < 120; ++x)
    for (int y = 48; y <= 52; ++y) mask(x, y) = 1;
  for (int x = 70; x <= 90; ++x)
    for (int y = 30; y <= 45; ++y) mask(x, y) = 1;
  perch::workspace ws;
  const perch::tree_pixel_counter tree(mask.view());

  const std::vector<perch::window_measures> windows = {
      window(0, 0, 10, 5.0f, 40.0f),    // viable, P = 0.8·5/35 + 0.2·10/80
      window(0, 5, 15, 5.0f, 40.0f),    // viable, same penalty, too close to the first
      window(0, 60, 80, 0.0f, 30.0f),   // ideal geometry but buried in twigs
      window(1, 0, 40, 50.0f, 40.0f),   // too steep (by 15°)
      window(1, 9, 45, 36.0f, 40.0f),   // too steep (by 1°): the near miss
      window(1, 20, 55, 50.0f, 200.0f), // too steep and too thick
      window(2, 0, 110, 2.0f, 105.0f),  // viable, P = 0.8·2/35 + 0.2·75/80
  };
  using constraints = perch::all_of<perch::diameter_range, perch::max_slope, perch::clutter>;
  const constraints c{perch::diameter_range{30.0f, 110.0f, 0.0f}, perch::max_slope{35.0f},
                      perch::clutter{.margin_mm = 20.0f, .max_share = 0.1f}};
  auto make_context = [&tree](const perch::window_measures& m) {
    const perch::point2f centre = perch::to_point(m.centre);
    return perch::window_context(tree, m, centre - perch::point2f(10, 0),
                                 centre + perch::point2f(10, 0), 2.5f, perch::point2f(0, -1));
  };
  auto ranked = perch::rank_windows(windows, c, perch::pli_penalty{}, make_context, ws,
                                    {.top_k = 5, .site_separation_mm = 20.0f});
  REQUIRE(ranked);
  CHECK(ranked->windows == 7);
  CHECK(ranked->viable == 3);
  REQUIRE(ranked->sites.size() == 2);  // the second viable window is within 20 mm of the first
  CHECK(ranked->sites[0].window.centre.x == 10);
  CHECK(ranked->sites[0].penalty == doctest::Approx(0.8f * 5 / 35 + 0.2f * 10 / 80));
  CHECK(ranked->sites[0].rank == 0);
  CHECK(ranked->sites[1].window.centre.x == 110);
  CHECK(ranked->sites[1].rank == 1);

  REQUIRE(ranked->rejections.size() == 3);
  CHECK(ranked->rejections[0].constraint == "diameter");
  CHECK(ranked->rejections[0].windows == 1);  // the thick, steep one fails diameter first
  CHECK(ranked->rejections[1].windows == 2);
  CHECK(ranked->rejections[2].constraint == "clutter");
  CHECK(ranked->rejections[2].windows == 1);
  REQUIRE(ranked->near_misses[1].present);
  CHECK(ranked->near_misses[1].miss == doctest::Approx(1.0f));
  CHECK(ranked->near_misses[1].window.centre.x == 45);
  CHECK(!ranked->near_misses[0].present);  // nothing failed on diameter alone
  REQUIRE(ranked->near_misses[2].present);
  CHECK(ranked->near_misses[2].miss > 0.1f);

  // Deterministic and allocation-free on a warm workspace.
  ws.reset();
  perch::test::allocation_scope scope;
  auto again = perch::rank_windows(windows, c, perch::pli_penalty{}, make_context, ws,
                                   {.top_k = 5, .site_separation_mm = 20.0f});
  CHECK(scope.count() == 0);
  REQUIRE(again);
  CHECK(again->sites[0].penalty == ranked->sites[0].penalty);
}

TEST_CASE("rank: no viable window is a normal outcome") {
  perch::workspace ws;
  const std::vector<perch::window_measures> windows = {window(0, 0, 10, 80.0f, 40.0f)};
  auto ranked = perch::rank_windows(windows, perch::max_slope{}, perch::pli_penalty{},
                                    [](const perch::window_measures&) -> perch::window_context {
                                      PERCH_ASSERT(false, "no context constraint here");
                                      __builtin_unreachable();
                                    }, ws);
  REQUIRE(ranked);
  CHECK(ranked->sites.empty());
  CHECK(ranked->rejections[0].windows == 1);
}

TEST_CASE("rank: with an uncertain scale every rule in mm holds at both ends of it") {
  // A branch 5 px thick along row 50 (radius 2.5 px) and a line 26 px from its axis. clutter's
  // band reaches 2.5 px + 20 mm across: 22.5 px at 1 mm/px, 24.7 px at the fine end of ±10 %,
  // 27.5 px at the fine end of ±20 % (the line inside). Diameters: 34 mm is 27.2 mm at the fine
  // end of ±20 %; 105 mm is 115.5 mm at the coarse end of ±10 %.
  perch::image<std::uint8_t> mask(200, 100, 0);
  for (int x = 0; x < 200; ++x)
    for (int y = 48; y <= 52; ++y) mask(x, y) = 1;
  for (int x = 0; x < 200; ++x) mask(x, 24) = 1;
  perch::workspace ws;
  const perch::tree_pixel_counter tree(mask.view());
  const std::vector<perch::window_measures> windows = {
      window(0, 0, 40, 0.0f, 34.0f),    // thin end
      window(1, 0, 100, 0.0f, 60.0f),   // middle of the range
      window(2, 0, 160, 0.0f, 105.0f),  // thick end
  };
  using constraints = perch::all_of<perch::diameter_range, perch::clutter>;
  const constraints c{perch::diameter_range{30.0f, 110.0f, 0.0f},
                      perch::clutter{.margin_mm = 20.0f, .max_share = 0.0f}};
  auto make_context = [&tree](const perch::window_measures& m) {
    const perch::point2f centre = perch::to_point(m.centre);
    return perch::window_context(tree, m, centre - perch::point2f(10, 0),
                                 centre + perch::point2f(10, 0), 2.5f, perch::point2f(0, -1));
  };
  auto exact = perch::rank_windows(windows, c, perch::pli_penalty{}, make_context, ws, {}, 0.0f);
  REQUIRE(exact);
  CHECK(exact->viable == 3);
  auto some = perch::rank_windows(windows, c, perch::pli_penalty{}, make_context, ws, {}, 0.1f);
  REQUIRE(some);
  CHECK(some->viable == 2);
  CHECK(some->rejections[0].windows == 1);  // 105 mm: 115.5 mm at the coarse end
  REQUIRE(some->near_misses[0].present);
  CHECK(some->near_misses[0].miss == doctest::Approx(5.5f));
  CHECK(some->sites[0].window.claw_diameter_mm == 34.0f);  // reported at the nominal scale
  auto wide = perch::rank_windows(windows, c, perch::pli_penalty{}, make_context, ws, {}, 0.2f);
  REQUIRE(wide);
  CHECK(wide->viable == 0);
  CHECK(wide->rejections[0].windows == 2);  // 34 mm and 105 mm: out of range at one end
  CHECK(wide->rejections[1].windows == 1);  // 60 mm: the band reaches the line at the fine end
  REQUIRE(wide->near_misses[0].present);
  CHECK(wide->near_misses[0].miss == doctest::Approx(2.8f));  // 27.2 mm at the fine end
}
