// SPDX-License-Identifier: BSL-1.0
#include "perch/graph/limb_surroundings.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <utility>
#include <vector>

#include "perch/core/image.hpp"
#include "perch/pli.hpp"
#include "support/find_perch_instances.hpp"

namespace {

using perch::image;
using perch::point2f;

void capsule(image<std::uint8_t>& m, point2f a, point2f b, float radius) {
  const point2f d = b - a;
  const float len2 = d.squaredNorm();
  for (int y = 0; y < m.height(); ++y)
    for (int x = 0; x < m.width(); ++x) {
      const point2f p(static_cast<float>(x), static_cast<float>(y));
      const float t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
      if ((p - (a + t * d)).norm() <= radius) m(x, y) = 255;
    }
}

/// `find_perch`'s graph and limbs (2 mm/px), with the limbs' surroundings rebuilt from them as
/// `find_perch` builds them: continuations, stretches, obstacle discs, the clearance cache.
struct surroundings {
  perch::workspace ws;
  perch::workspace own_ws;
  std::optional<perch::perch_result> result;
  const perch::perch_result& found() const { return *result; }
  std::vector<std::int32_t> next;
  std::vector<perch::branch_stretch> stretches;
  perch::limb_obstacles obstacles;
  std::span<const perch::limb_neighbourhood> around;
  perch::limb_clearance clearance;
};

void analyse(surroundings& s, const image<std::uint8_t>& mask, float mm_per_px = 2.0f,
             const perch::obstacle_options& options = {}) {
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{mm_per_px}, s.ws);
  REQUIRE(found);
  s.result.emplace(std::move(*found));
  const perch::skeleton_graph& graph = s.found().graph;
  s.next.assign(2 * static_cast<std::size_t>(graph.topology().edge_id_end()), 0);
  perch::limb_continuations(graph, perch::edge_continuations(s.next), perch::limb_options{});
  s.stretches.clear();
  for (const perch::skeleton_limb& l : s.found().limbs) s.stretches.push_back(perch::limb_stretch(graph, perch::edge_continuations(s.next), l));
  auto obstacles = perch::find_limb_obstacles(graph, s.found().limbs, perch::edge_continuations(s.next), s.stretches,
                                              s.found().skeleton, s.found().dist2, nullptr,
                                              s.found().mm_per_px, s.own_ws, options);
  REQUIRE(obstacles);
  s.obstacles = *obstacles;
  auto around = perch::detail::limb_neighbourhoods(s.found().limbs, s.obstacles.own, s.own_ws);
  REQUIRE(around);
  s.around = *around;
  s.clearance = perch::limb_clearance(s.obstacles.discs, s.around);
}

/// The limb whose points lie nearest row `y` (mask coordinates) on average.
std::size_t limb_along_row(const surroundings& s, float y) {
  std::size_t best = 0;
  float best_error = 1e30f;
  for (std::size_t l = 0; l < s.found().limbs.size(); ++l) {
    const perch::skeleton_limb& limb = s.found().limbs[l];
    float sum = 0;
    for (const perch::pixel p : limb.points)
      sum += std::abs(static_cast<float>(p.y + s.found().mask.offset.y) - y);
    const float error = sum / static_cast<float>(limb.points.size());
    if (error < best_error) {
      best_error = error;
      best = l;
    }
  }
  return best;
}

/// The smallest gap (px) over limb `l`'s points whose mask x lies in [x0, x1].
float gap_between(const surroundings& s, std::size_t l, int x0, int x1, float cap_px) {
  const perch::skeleton_limb& limb = s.found().limbs[l];
  float smallest = cap_px;
  for (std::size_t i = 0; i < limb.points.size(); ++i) {
    const int x = limb.points[i].x + s.found().mask.offset.x;
    if (x < x0 || x > x1) continue;
    smallest = std::min(smallest, s.clearance.smallest_gap_px(static_cast<std::int32_t>(l),
                                                              static_cast<std::uint32_t>(i),
                                                              static_cast<std::uint32_t>(i), cap_px));
  }
  return smallest;
}

std::size_t unowned_discs(const surroundings& s) {
  std::size_t count = 0;
  for (const perch::owned_disc& d : s.obstacles.discs.discs())
    if (d.owner == perch::unowned_disc) ++count;
  return count;
}

}  // namespace

TEST_CASE("limb_surroundings: two parallel limbs' gap is the gap between their outlines") {
  // Level bars of radius 10 px (40 mm at 2 mm/px) with surfaces `gap` px apart; away from the
  // round caps, every point of either sees the other's surface at the gap, within a pixel (the
  // outlines are pixel-sampled: a gap of g between the drawn capsules is g − 1 background rows).
  for (const float gap : {8.0f, 24.0f, 30.0f, 45.0f}) {
    image<std::uint8_t> mask(320, 200);
    capsule(mask, {20, 40}, {300, 40}, 10);
    capsule(mask, {20, 60 + gap}, {300, 60 + gap}, 10);
    surroundings s;
    analyse(s, mask);
    REQUIRE(s.found().limbs.size() == 2);
    CHECK(unowned_discs(s) == 0);  // no junctions: no discs for limbs leaving one
    CAPTURE(gap);
    for (const float row : {40.0f, 60.0f + gap}) {
      const std::size_t l = limb_along_row(s, row);
      CHECK(s.obstacles.own[l].contains(static_cast<std::int32_t>(l)));
      // Every interior point, one at a time and as one range.
      for (int x = 40; x <= 280; x += 20) {
        const float g = gap_between(s, l, x, x, 200.0f);
        CAPTURE(x);
        CHECK(std::abs(g - gap) <= 1.01f);
      }
      CHECK(std::abs(gap_between(s, l, 40, 280, 200.0f) - gap) <= 1.01f);
      // Beyond the cap the search stops: the cap, exactly.
      CHECK(gap_between(s, l, 40, 280, gap - 3.0f) == gap - 3.0f);
    }
  }
}

TEST_CASE("limb_surroundings: window_context::limb_gap_mm reads the gap in mm; the cache is exact") {
  image<std::uint8_t> mask(320, 200);
  capsule(mask, {20, 40}, {300, 40}, 10);
  capsule(mask, {20, 90}, {300, 90}, 10);  // surfaces 30 px = 60 mm apart
  surroundings s;
  analyse(s, mask);
  REQUIRE(s.found().limbs.size() == 2);
  const std::size_t l = limb_along_row(s, 40.0f);
  const perch::skeleton_limb& limb = s.found().limbs[l];
  perch::window_measures m;
  m.limb = static_cast<std::int32_t>(l);
  m.first = 60;
  m.last = 150;
  m.mm_per_px = 2.0f;
  const perch::tree_pixel_counter tree(s.found().mask.pixels);
  const perch::point2f a = perch::to_point(limb.points[m.first]);
  const perch::point2f b = perch::to_point(limb.points[m.last]);
  const perch::window_context context(tree, m, a, b, 10.0f, {0, -1}, &s.clearance);
  // Asked first with a cap below the gap (the cache then holds "nothing within 20 mm"), then
  // above it: the second search looks further, it does not reuse the first's cap.
  CHECK(context.limb_gap_mm(20.0f) == 20.0f);
  const float gap_mm = context.limb_gap_mm(150.0f);
  CHECK(std::abs(gap_mm - 60.0f) <= 2.01f);
  CHECK(context.limb_gap_mm(150.0f) == gap_mm);
  CHECK(context.limb_gap_mm(40.0f) == 40.0f);  // found nearer than before: still capped
  CHECK(context.limb_gap_mm(1000.0f) == gap_mm);
  // A fresh cache (no earlier queries) gives the same.
  surroundings fresh;
  analyse(fresh, mask);
  const perch::window_context again(tree, m, a, b, 10.0f, {0, -1}, &fresh.clearance);
  CHECK(again.limb_gap_mm(1000.0f) == gap_mm);
  // The clearance constraint misses by what the gap lacks of its margin (plus its uncertainty).
  const perch::clearance rule{.margin_mm = 70.0f, .uncertainty_px = 0.0f};
  CHECK(rule(m, context) == doctest::Approx(70.0f - gap_mm));
  CHECK(perch::clearance{.margin_mm = 50.0f, .uncertainty_px = 0.0f}(m, context) == 0.0f);
  // Without the other limbs' surroundings, or for an unknown limb: nothing around it.
  const perch::window_context bare(tree, m, a, b, 10.0f, {0, -1});
  CHECK(bare.limb_gap_mm(70.0f) == 70.0f);
  perch::window_measures unknown = m;
  unknown.limb = 7;
  const perch::window_context lost(tree, unknown, a, b, 10.0f, {0, -1}, &s.clearance);
  CHECK(lost.limb_gap_mm(70.0f) == 70.0f);
}

TEST_CASE("limb_surroundings: limbs thinner than twig_max_mm are no obstacle; thicker ones are") {
  // A thick bar (radius 10 px) and a parallel one 24 px below its surface: radius 3 (7 px =
  // 14 mm across at 2 mm/px, under the 20 mm twig limit even a pixel wider) or radius 6
  // (13 px = 26 mm).
  for (const float radius : {3.0f, 6.0f}) {
    image<std::uint8_t> mask(320, 200);
    capsule(mask, {20, 40}, {300, 40}, 10);
    capsule(mask, {20, 74 + radius}, {300, 74 + radius}, radius);
    surroundings s;
    analyse(s, mask);
    REQUIRE(s.found().limbs.size() == 2);
    const std::size_t thick = limb_along_row(s, 40.0f);
    const std::size_t thin = limb_along_row(s, 74 + radius);
    REQUIRE(thick != thin);
    CAPTURE(radius);
    // The thin bar always sees the thick one.
    CHECK(std::abs(gap_between(s, thin, 40, 280, 200.0f) - 24.0f) <= 1.01f);
    if (radius < 5)
      CHECK(gap_between(s, thick, 0, 320, 200.0f) == 200.0f);
    else
      CHECK(std::abs(gap_between(s, thick, 40, 280, 200.0f) - 24.0f) <= 1.01f);
  }
  // A 9 px bar (18 mm) is a twig only if its width is trusted to the pixel: within a pixel's
  // uncertainty of the limit it counts.
  image<std::uint8_t> nine(320, 200);
  capsule(nine, {20, 40}, {300, 40}, 10);
  capsule(nine, {20, 78}, {300, 78}, 4);
  surroundings cautious;
  analyse(cautious, nine);
  CHECK(std::abs(gap_between(cautious, limb_along_row(cautious, 40.0f), 40, 280, 200.0f) - 24.0f) <=
        1.01f);
  surroundings trusting;
  analyse(trusting, nine, 2.0f, perch::obstacle_options{.twig_max_mm = 20.0f, .uncertainty_px = 0.0f});
  CHECK(gap_between(trusting, limb_along_row(trusting, 40.0f), 0, 320, 200.0f) == 200.0f);
  // The limit is in mm: at 4 mm/px the 7 px bar is 28 mm across, an obstacle; and a 40 mm
  // limit makes the 13 px bar at 2 mm/px (26 mm) a twig.
  image<std::uint8_t> mask(320, 200);
  capsule(mask, {20, 40}, {300, 40}, 10);
  capsule(mask, {20, 77}, {300, 77}, 3);
  surroundings fine;
  analyse(fine, mask, 2.0f);
  CHECK(gap_between(fine, limb_along_row(fine, 40.0f), 0, 320, 200.0f) == 200.0f);
  surroundings coarse;
  analyse(coarse, mask, 4.0f);
  CHECK(std::abs(gap_between(coarse, limb_along_row(coarse, 40.0f), 40, 280, 200.0f) - 24.0f) <=
        1.01f);
  image<std::uint8_t> wider(320, 200);
  capsule(wider, {20, 40}, {300, 40}, 10);
  capsule(wider, {20, 80}, {300, 80}, 6);
  surroundings lenient;
  analyse(lenient, wider, 2.0f, perch::obstacle_options{.twig_max_mm = 40.0f});
  CHECK(gap_between(lenient, limb_along_row(lenient, 40.0f), 0, 320, 200.0f) == 200.0f);
  CHECK(!perch::obstacle_options{.twig_max_mm = -1.0f}.validate());
  CHECK(!perch::obstacle_options{.twig_max_mm = std::nanf("")}.validate());
  CHECK(!perch::obstacle_options{.uncertainty_px = -1.0f}.validate());
  CHECK(perch::obstacle_options{}.validate());
}

TEST_CASE("limb_surroundings: a side twig is no obstacle to the limb it leaves, a side limb is") {
  // A level limb (radius 10 px) with a limb rising from its middle at x = 200.
  // A 5 px twig: the limb runs on through the junction (`limb_continuations`), and the twig's
  // skeleton inside the limb's body is read at the twig's own radius, under the twig limit.
  image<std::uint8_t> twig(400, 200);
  capsule(twig, {20, 150}, {380, 150}, 10);
  capsule(twig, {200, 150}, {200, 20}, 2.5f);
  surroundings with_twig;
  analyse(with_twig, twig);
  const std::size_t through = limb_along_row(with_twig, 150.0f);
  REQUIRE(with_twig.found().limbs[through].points.size() > 300);  // one limb, end to end
  CHECK(gap_between(with_twig, through, 0, 400, 200.0f) == 200.0f);
  // Every disc counted (no twig limit): the twig is there, from the limb's axis up.
  surroundings strict;
  analyse(strict, twig, 2.0f, perch::obstacle_options{.twig_max_mm = 0.0f});
  const std::size_t limb = limb_along_row(strict, 150.0f);
  for (const int dx : {30, 60}) {
    // |p − c| − r(c) − r(p) to the twig's base disc on the limb's axis: dx − ~2.5 − ~10.5.
    const float g = std::min(gap_between(strict, limb, 200 + dx, 200 + dx, 200.0f),
                             gap_between(strict, limb, 200 - dx, 200 - dx, 200.0f));
    CAPTURE(dx);
    CHECK(std::abs(g - (static_cast<float>(dx) - 13.0f)) <= 1.5f);
  }

  // A 19 px side limb (38 mm): it ends the level limb there, so three limbs meet. Each half
  // sees the side limb and the other half from the junction on (discs for the limbs leaving it
  // there), and the side limb sees the level limb.
  image<std::uint8_t> side(400, 200);
  capsule(side, {20, 150}, {380, 150}, 10);
  capsule(side, {200, 150}, {200, 20}, 9.0f);
  surroundings tee;
  analyse(tee, side);
  REQUIRE(tee.found().limbs.size() == 3);
  CHECK(unowned_discs(tee) == 2);  // one at each half's junction end
  for (const perch::owned_disc& d : tee.obstacles.discs.discs()) {
    if (d.owner != perch::unowned_disc) continue;
    // On the level limb's axis beside the node, as wide as the limbs leaving there.
    CHECK(std::abs(d.y + static_cast<float>(tee.found().mask.offset.y) - 150.0f) <= 2.0f);
    CHECK(std::abs(d.x + static_cast<float>(tee.found().mask.offset.x) - 200.0f) <= 12.0f);
    CHECK(d.radius >= 9.0f);
    CHECK(d.radius <= 11.0f);
  }
  std::size_t halves = 0;
  for (std::size_t l = 0; l < 3; ++l) {
    const perch::skeleton_limb& piece = tee.found().limbs[l];
    const int x0 = piece.points.front().x + tee.found().mask.offset.x;
    const int x1 = piece.points.back().x + tee.found().mask.offset.x;
    if (std::abs(x1 - x0) < 100) {  // the side limb: the level limb's surface below it
      const float g = gap_between(tee, l, 190, 210, 200.0f);
      CHECK(g < 0.0f);
      continue;
    }
    ++halves;
    const int sign = x1 > x0 ? 1 : -1;
    for (const int dx : {40, 60, 90}) {
      // dx from the side limb's axis: its surface at dx − 10, less this limb's radius ~10.5.
      const float g = gap_between(tee, l, 200 + sign * dx, 200 + sign * dx, 200.0f);
      CAPTURE(dx);
      CAPTURE(g);
      CHECK(g <= static_cast<float>(dx) - 18.0f);
      CHECK(g >= static_cast<float>(dx) - 24.0f);
    }
  }
  CHECK(halves == 2);
}

TEST_CASE("limb_surroundings: grounded components reach the bottom row or are the main tree") {
  // Hand-made limbs of three components in a frame whose last row is 99.
  const std::vector<perch::pixel> trunk_points{{10, 60}, {10, 70}, {10, 80}, {10, 90}};
  const std::vector<float> trunk_radius{3, 3, 3, 4};  // 90 + 4 + 2 = 96: 3 px short
  const std::vector<perch::pixel> low_points{{50, 92}, {60, 92}};
  const std::vector<float> low_radius{2, 5};  // 92 + 5 + 2 = 99: reaches it
  const std::vector<perch::pixel> blob_points{{80, 10}, {81, 10}, {82, 10}, {83, 10}, {84, 10}};
  const std::vector<float> blob_radius{8, 8, 8, 8, 8};  // the most area: the main tree
  auto limb = [](const std::vector<perch::pixel>& p, const std::vector<float>& r, int component) {
    perch::skeleton_limb l;
    l.points = p;
    l.radius_px = r;
    l.component = component;
    return l;
  };
  std::vector<perch::skeleton_limb> limbs{limb(trunk_points, trunk_radius, 0),
                                          limb(low_points, low_radius, 1),
                                          limb(blob_points, blob_radius, 2),
                                          limb(blob_points, blob_radius, -1),  // no component
                                          limb(blob_points, blob_radius, 9)};  // out of range
  std::vector<std::uint8_t> grounded(3, 7);
  std::vector<float> area(3, -1.0f);
  perch::grounded_components(limbs, 99.0f, grounded, area);
  CHECK(area[0] == doctest::Approx(9.0f + 9.0f + 9.0f + 16.0f));
  CHECK(area[1] == doctest::Approx(4.0f + 25.0f));
  CHECK(area[2] == doctest::Approx(5 * 64.0f));
  CHECK(grounded[0] == 0);  // 3 px short of the bottom row
  CHECK(grounded[1] == 1);  // its outline within 2 px of it
  CHECK(grounded[2] == 1);  // the main tree
  // A wider reach grounds the trunk.
  perch::grounded_components(limbs, 99.0f, grounded, area, 5.0f);
  CHECK(grounded[0] == 1);
  // The blob shrunk to one point of radius 5 (area 25): no longer the main tree, not grounded;
  // the trunk (area 43) is.
  const std::vector<float> small_radius{5};
  limbs[2].radius_px = small_radius;
  limbs[2].points = std::span<const perch::pixel>(blob_points).first(1);
  perch::grounded_components(limbs, 99.0f, grounded, area);
  CHECK(area[2] == doctest::Approx(25.0f));
  CHECK(grounded[0] == 1);
  CHECK(grounded[1] == 1);
  CHECK(grounded[2] == 0);
  // Nothing at all: nothing grounded, no crash.
  perch::grounded_components({}, 99.0f, std::span<std::uint8_t>{}, std::span<float>{});
}

TEST_CASE("limb_surroundings: a detached blob above the tree is not grounded, unless the largest") {
  // A trunk from the bottom edge with a limb, and a bar floating above it.
  image<std::uint8_t> mask(400, 300);
  capsule(mask, {100, 340}, {100, 150}, 20);
  capsule(mask, {100, 200}, {350, 200}, 10);
  capsule(mask, {150, 60}, {350, 60}, 12);
  surroundings s;
  analyse(s, mask);
  const perch::skeleton_graph& graph = s.found().graph;
  const auto components = static_cast<std::size_t>(graph.component_count());
  REQUIRE(components == 2);
  std::vector<std::uint8_t> grounded(components);
  std::vector<float> area(components);
  const float bottom = static_cast<float>(s.found().mask.analysed_height - 1 -
                                          s.found().mask.offset.y);
  perch::grounded_components(s.found().limbs, bottom, grounded, area);
  const auto bar = static_cast<std::size_t>(s.found().limbs[limb_along_row(s, 60.0f)].component);
  const auto tree = static_cast<std::size_t>(s.found().limbs[limb_along_row(s, 200.0f)].component);
  REQUIRE(bar != tree);
  CHECK(grounded[tree] == 1);
  CHECK(grounded[bar] == 0);
  // Alone in the frame, the bar is the main tree.
  image<std::uint8_t> alone(400, 300);
  capsule(alone, {150, 60}, {350, 60}, 12);
  surroundings single;
  analyse(single, alone);
  std::vector<std::uint8_t> one(1, 0);
  std::vector<float> one_area(1);
  REQUIRE(single.found().graph.component_count() == 1);
  perch::grounded_components(single.found().limbs,
                             static_cast<float>(single.found().mask.analysed_height - 1 -
                                                single.found().mask.offset.y),
                             one, one_area);
  CHECK(one[0] == 1);
}

TEST_CASE("limb_surroundings: a too-small borrowed workspace is a status") {
  image<std::uint8_t> mask(320, 200);
  capsule(mask, {20, 40}, {300, 40}, 10);
  capsule(mask, {20, 90}, {300, 90}, 10);
  surroundings s;
  analyse(s, mask);
  std::size_t skeleton_pixels = 0;
  for (int y = 0; y < s.found().skeleton.height(); ++y)
    for (int x = 0; x < s.found().skeleton.width(); ++x)
      if (s.found().skeleton(x, y) != 0) ++skeleton_pixels;
  const std::size_t bytes = perch::limb_obstacles_workspace_bytes(
      s.found().limbs.size(), skeleton_pixels, s.found().skeleton.width(),
      s.found().skeleton.height());
  std::vector<std::byte> buffer(bytes / 2);
  perch::workspace small{std::span<std::byte>(buffer)};
  auto obstacles =
      perch::find_limb_obstacles(s.found().graph, s.found().limbs, perch::edge_continuations(s.next), s.stretches,
                                 s.found().skeleton, s.found().dist2, nullptr, 2.0f, small);
  REQUIRE(!obstacles);
  CHECK(obstacles.error().code == perch::errc::workspace_too_small);
  // The size query is enough.
  std::vector<std::byte> enough(bytes + perch::workspace::alignment);
  perch::workspace fits{std::span<std::byte>(enough)};
  CHECK(perch::find_limb_obstacles(s.found().graph, s.found().limbs, perch::edge_continuations(s.next), s.stretches,
                                   s.found().skeleton, s.found().dist2, nullptr, 2.0f, fits));
}
