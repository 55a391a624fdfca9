// SPDX-License-Identifier: BSL-1.0
#include "perch/pli.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <cstdint>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "allocation_counter.hpp"
#include "perch/core/image.hpp"
#include "support/find_perch_instances.hpp"

namespace {

using perch::errc;
using perch::image;
using perch::perch_outcome;

/// Fills the pixels whose centres lie within `radius` of the segment a–b.
void capsule(image<std::uint8_t>& m, perch::point2f a, perch::point2f b, float radius) {
  const perch::point2f d = b - a;
  const float len2 = d.squaredNorm();
  for (int y = 0; y < m.height(); ++y)
    for (int x = 0; x < m.width(); ++x) {
      const perch::point2f p(static_cast<float>(x), static_cast<float>(y));
      const float t = len2 > 0 ? std::clamp((p - a).dot(d) / len2, 0.0f, 1.0f) : 0.0f;
      if ((p - (a + t * d)).norm() <= radius) m(x, y) = 255;
    }
}

/// A trunk 90 px wide rising from the bottom edge and one straight limb leaving it at
/// `angle_deg` above the horizontal, `limb_px` wide (2 mm/px: trunk 180 mm).
image<std::uint8_t> t_tree(float angle_deg, float limb_px, int width = 640, int height = 480) {
  image<std::uint8_t> m(width, height);
  const float cx = 160;
  capsule(m, {cx, static_cast<float>(height + 40)}, {cx, 120}, 45);
  const float a = angle_deg * std::numbers::pi_v<float> / 180.0f;
  const perch::point2f start(cx, 260);
  capsule(m, start, start + 420.0f * perch::point2f(std::cos(a), -std::sin(a)), 0.5f * limb_px);
  return m;
}

}  // namespace

TEST_CASE("find_perch: a T tree perches on the limb, level, at its diameter") {
  const auto mask = t_tree(0.0f, 31.0f);
  perch::workspace ws;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(found);
  REQUIRE(found->outcome == perch_outcome::found);
  const perch::perch_site& best = found->sites.front();
  CHECK(best.window.centre.x > 160 + 45);  // on the limb, not the trunk
  CHECK(std::abs(best.window.centre.y - 260) <= 2);
  CHECK(best.window.slope_deg < 3.0f);
  CHECK(best.window.claw_diameter_mm == doctest::Approx(62.0f).epsilon(0.05));
  CHECK(best.penalty >= 0.0f);
  CHECK(best.penalty <= 1.0f);
  CHECK(found->mm_per_px == doctest::Approx(2.0f));
  CHECK(found->graph.branch_count() > 0);
  CHECK(found->viable > 0);
  CHECK(found->windows >= found->viable);
  // Ranked sites are sorted and distinct.
  for (std::size_t i = 1; i < found->sites.size(); ++i) {
    CHECK(found->sites[i - 1].penalty <= found->sites[i].penalty);
    CHECK(found->sites[i].rank == i);
  }
}

TEST_CASE("find_perch: windows run along a limb through the junction where a twig leaves") {
  // A level limb 19 px (38 mm) thick, 150 px long, with a 2 px twig rising from its middle: each
  // half is shorter than the 90 px window, the limb is not.
  image<std::uint8_t> mask(200, 60);
  capsule(mask, {25, 40}, {175, 40}, 9.5f);
  capsule(mask, {100, 40}, {100, 2}, 1.0f);
  perch::workspace ws;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(found);
  REQUIRE(found->outcome == perch_outcome::found);
  const perch::perch_site& best = found->sites.front();
  const perch::skeleton_limb& limb = found->limbs[static_cast<std::size_t>(best.window.limb)];
  const perch::pixel first = limb.points[best.window.first];
  const perch::pixel last = limb.points[best.window.last];
  CHECK(std::min(first.x, last.x) + found->mask.offset.x < 100);
  CHECK(std::max(first.x, last.x) + found->mask.offset.x > 100);
  CHECK(std::abs(best.window.centre.y - 40) <= 1);
  // Without joining limbs through side twigs (neither a thin enough leaf by the pipe model nor
  // anything known to be a twig by the platform's measure), no window fits.
  perch::perch_options options;
  options.limbs.side_area_share_max = 0.0f;
  options.obstacles.twig_max_mm = 0.0f;
  auto split = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws,
                                 options);
  REQUIRE(split);
  CHECK(split->outcome == perch_outcome::no_perch);
  CHECK(split->windows == 0);
}

TEST_CASE("find_perch: pinholes in a limb are filled, so the limb stays whole") {
  // The limb of the twig test without the twig, with a one-pixel pinhole and a 2 × 2 one (a
  // segmenter's speckle): the skeleton would circle each and cut the limb into pieces shorter
  // than a window.
  image<std::uint8_t> mask(200, 60);
  capsule(mask, {25, 40}, {175, 40}, 9.5f);
  mask(60, 36) = 0;
  for (int y = 44; y < 46; ++y)
    for (int x = 99; x < 101; ++x) mask(x, y) = 0;
  perch::workspace ws;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(found);
  CHECK(found->holes.filled == 2);
  CHECK(found->holes.filled_pixels == 5);
  CHECK(found->mask.pixels(60 - found->mask.offset.x, 36 - found->mask.offset.y) != 0);
  CHECK(mask(60, 36) == 0);  // the caller's mask is not touched
  REQUIRE(found->outcome == perch_outcome::found);
  CHECK(std::abs(found->sites.front().window.centre.y - 40) <= 1);
  // Filling only the single pixel leaves the 2 × 2 hole 4 px below the axis: the skeleton
  // circles it, and the limb runs on along the thick strand above it (the strand below is
  // thinner than a twig), so the perch stays.
  perch::perch_options options;
  options.max_hole_px = 3;
  auto split =
      perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws, options);
  REQUIRE(split);
  CHECK(split->holes.filled == 1);
  CHECK(split->outcome == perch_outcome::found);
  // Without the twig rule (nothing is a twig), the strand below ends the limb at the hole, and
  // the pieces are shorter than a window.
  options.obstacles.twig_max_mm = 0;
  auto cut =
      perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws, options);
  REQUIRE(cut);
  CHECK(cut->outcome == perch_outcome::no_perch);
  options.max_hole_px = -1;
  auto bad =
      perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws, options);
  REQUIRE(!bad);
  CHECK(bad.error().code == errc::invalid_parameter);
}

TEST_CASE("find_perch: a site never lies on a filled pinhole") {
  // The perch pixel of a level limb, then the same limb with a pinhole punched there: the
  // window's middle moves to the nearest tree pixel of its centreline (found by fuzzing).
  image<std::uint8_t> mask(200, 60);
  capsule(mask, {25, 40}, {175, 40}, 9.5f);
  perch::workspace ws;
  auto solid = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(solid);
  REQUIRE(solid->outcome == perch_outcome::found);
  const perch::pixel at = solid->sites.front().window.centre;
  mask(at.x, at.y) = 0;
  auto holed = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(holed);
  CHECK(holed->holes.filled == 1);
  REQUIRE(holed->outcome == perch_outcome::found);
  for (const perch::perch_site& site : holed->sites) {
    const perch::pixel c = site.window.centre;
    CHECK(mask(c.x, c.y) != 0);
    const perch::skeleton_limb& limb = holed->limbs[static_cast<std::size_t>(site.window.limb)];
    const perch::pixel p = limb.points[site.window.middle];
    CHECK(perch::pixel{p.x + holed->mask.offset.x, p.y + holed->mask.offset.y} == c);
  }
  const perch::pixel moved = holed->sites.front().window.centre;
  CHECK(std::abs(moved.x - at.x) + std::abs(moved.y - at.y) <= 2);
}

TEST_CASE("find_perch: slope of the limb is measured and constrained") {
  perch::workspace ws;
  for (const float angle : {10.0f, 20.0f, 30.0f}) {
    CAPTURE(angle);
    const auto mask = t_tree(angle, 31.0f);
    auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
    REQUIRE(found);
    REQUIRE(found->outcome == perch_outcome::found);
    CHECK(found->sites.front().window.slope_deg == doctest::Approx(angle).epsilon(0.1));
  }
  // A 50° limb is too steep for the claw: no perch, and the slope constraint says so.
  const auto steep = t_tree(50.0f, 31.0f);
  auto found = perch::find_perch(steep.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(found);
  CHECK(found->outcome == perch_outcome::no_perch);
  bool slope_rejected = false;
  for (const auto& r : found->rejections)
    if (r.constraint == "max_slope") slope_rejected = r.windows > 0;
  CHECK(slope_rejected);
}

TEST_CASE("find_perch: a limb too thick for the claw is a normal no-perch with reasons") {
  const auto mask = t_tree(0.0f, 71.0f);  // 142 mm > 110 mm
  perch::workspace ws;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(found);
  CHECK(found->outcome == perch_outcome::no_perch);
  CHECK(found->sites.empty());
  std::uint32_t rejected = 0;
  for (const auto& r : found->rejections) rejected += r.windows;
  CHECK(rejected == found->windows);
  bool diameter_miss = false;
  for (const auto& m : found->near_misses)
    if (m.constraint == "diameter" && m.present) diameter_miss = m.miss > 0;
  CHECK(diameter_miss);
}

TEST_CASE("find_perch: an empty mask is no_tree, not an error") {
  image<std::uint8_t> mask(64, 48);
  perch::workspace ws;
  auto found = perch::find_perch(mask.view(), ws);
  REQUIRE(found);
  CHECK(found->outcome == perch_outcome::no_tree);
  CHECK(found->sites.empty());
}

TEST_CASE("find_perch: no allocation on the second call with the same workspace") {
  const auto mask = t_tree(10.0f, 31.0f);
  perch::workspace ws;
  REQUIRE(perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws));
  perch::test::allocation_scope scope;
  auto again = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  CHECK(scope.count() == 0);
  REQUIRE(again);
  CHECK(again->outcome == perch_outcome::found);
}

TEST_CASE("find_perch: deterministic, and a strided view gives the same answer") {
  const auto mask = t_tree(15.0f, 35.0f);
  const int stride = mask.width() + 13;
  std::vector<std::uint8_t> padded(static_cast<std::size_t>(stride * mask.height()), 0);
  for (int y = 0; y < mask.height(); ++y)
    for (int x = 0; x < mask.width(); ++x)
      padded[static_cast<std::size_t>(y * stride + x)] = mask(x, y);
  perch::image_view<const std::uint8_t> strided(padded.data(), mask.width(), mask.height(), stride);
  perch::workspace ws1, ws2;
  auto a = perch::find_perch(mask.view(), ws1);
  auto b = perch::find_perch(strided, ws2);
  REQUIRE(a);
  REQUIRE(b);
  REQUIRE(a->sites.size() == b->sites.size());
  for (std::size_t i = 0; i < a->sites.size(); ++i) {
    CHECK(a->sites[i].window.centre == b->sites[i].window.centre);
    CHECK(a->sites[i].penalty == b->sites[i].penalty);
    CHECK(a->sites[i].window.slope_deg == b->sites[i].window.slope_deg);
  }
}

namespace {

// A user's skeletoniser that does not opt in to the row runs; and one that does
// (`RowRunSkeletoniser`), saying whether the runs it was handed were those of its mask.
struct medial_axis_scanning {
  static constexpr std::string_view name = "medial_axis_scanning";
  static constexpr std::size_t workspace_bytes(int width, int height) noexcept {
    return perch::medial_axis::workspace_bytes(width, height);
  }
  perch::status operator()(perch::image_view<const std::uint8_t> mask,
                           perch::image_view<const std::uint32_t> dist2,
                           perch::image_view<std::uint8_t> skeleton,
                           perch::workspace& ws) const noexcept {
    return perch::medial_axis{}(mask, dist2, skeleton, ws);
  }
};
struct medial_axis_reading_runs : medial_axis_scanning {
  static constexpr std::string_view name = "medial_axis_reading_runs";
  bool* handed_runs = nullptr;
  using medial_axis_scanning::operator();
  perch::status operator()(perch::image_view<const std::uint8_t> mask,
                           perch::image_view<const std::uint32_t> dist2,
                           perch::image_view<std::uint8_t> skeleton, perch::workspace& ws,
                           const perch::row_runs& runs) const noexcept {
    *handed_runs = runs.describes(mask) && runs.size() > 0;
    return perch::medial_axis{}(mask, dist2, skeleton, ws, runs);
  }
};
static_assert(perch::RowRunSkeletoniser<perch::medial_axis>);
static_assert(perch::RowRunSkeletoniser<perch::zhang_suen>);
static_assert(perch::RowRunSkeletoniser<perch::guo_hall>);
static_assert(perch::RowRunSkeletoniser<medial_axis_reading_runs>);
static_assert(perch::Skeletoniser<medial_axis_scanning>);
static_assert(!perch::RowRunSkeletoniser<medial_axis_scanning>);

}  // namespace

TEST_CASE("find_perch: a user's skeletoniser opts in to the row runs like perch's own") {
  const auto mask = t_tree(15.0f, 35.0f);
  bool handed_runs = false;
  perch::workspace ws1, ws2, ws3;
  auto own = perch::find_perch(mask.view(), ws1);
  auto reading = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::trunk_prior{},
                                   medial_axis_reading_runs{{}, &handed_runs}, ws2);
  auto scanning = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::trunk_prior{},
                                    medial_axis_scanning{}, ws3);
  REQUIRE(own);
  REQUIRE(reading);
  REQUIRE(scanning);
  CHECK(handed_runs);
  REQUIRE(own->mask.runs.describes(perch::image_view<const std::uint8_t>(own->mask.pixels)));
  for (const auto* other : {&*reading, &*scanning}) {
    REQUIRE(other->sites.size() == own->sites.size());
    for (std::size_t i = 0; i < own->sites.size(); ++i) {
      CHECK(other->sites[i].window.centre == own->sites[i].window.centre);
      CHECK(other->sites[i].penalty == own->sites[i].penalty);
    }
  }
}

TEST_CASE("find_perch: listed runs and scanned rows give the kernels' distances and skeleton") {
  // find_perch lists the tree's runs once for the distance transform and the skeleton; a
  // speckled mask with more runs than it lists (a checkerboard half) makes both scan instead.
  // Either way the result must be what the kernels give on the prepared mask.
  image<std::uint8_t> speckled(160, 120);
  capsule(speckled, {80, 160}, {80, 40}, 20);
  for (int y = 0; y < 60; ++y)
    for (int x = 0; x < 160; ++x) speckled(x, y) = (x + y) % 2 == 0 ? 1 : 0;
  const auto limb = t_tree(15.0f, 35.0f);
  const image<std::uint8_t>* masks[] = {&speckled, &limb};
  for (const image<std::uint8_t>* mask : masks) {
    perch::workspace ws;
    const auto found = perch::find_perch(mask->view(), ws);
    REQUIRE(found);
    const auto tree = perch::image_view<const std::uint8_t>(found->mask.pixels);
    const int w = tree.width(), h = tree.height();
    perch::workspace own;
    image<std::uint32_t> d2(w, h);
    image<std::uint8_t> skeleton(w, h);
    REQUIRE(perch::distance_transform_sq(tree, d2.view(), own));
    REQUIRE(perch::medial_axis{}(tree, d2.view(), skeleton.view(), own));
    bool same = true;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x)
        same = same && found->skeleton(x, y) == skeleton(x, y) &&
               (tree(x, y) == 0 || found->dist2(x, y) == d2(x, y));
    CHECK(same);
  }
}

TEST_CASE("find_perch: downscaling by 0.5 finds the same site within a few pixels") {
  const auto mask = t_tree(5.0f, 31.0f);
  perch::workspace ws;
  auto full = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(full);
  REQUIRE(full->outcome == perch_outcome::found);
  const perch::perch_site best = full->sites.front();
  perch::perch_options half;
  half.downscale = 0.5f;
  auto reduced =
      perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws, half);
  REQUIRE(reduced);
  REQUIRE(reduced->outcome == perch_outcome::found);
  const perch::perch_site& r = reduced->sites.front();
  CHECK(reduced->mm_per_px == doctest::Approx(2.0f));
  CHECK(std::abs(r.window.slope_deg - best.window.slope_deg) < 2.0f);
  CHECK(std::abs(r.window.claw_diameter_mm - best.window.claw_diameter_mm) < 6.0f);
  // On the same limb (within one window of the full-resolution site).
  CHECK(std::abs(r.window.centre.y - best.window.centre.y) <= 40);
}

TEST_CASE("find_perch: every site says which way its branch runs") {
  perch::workspace ws;
  for (const float angle : {0.0f, 20.0f, -15.0f}) {
    for (const bool mirrored : {false, true}) {
      CAPTURE(angle);
      CAPTURE(mirrored);
      auto mask = t_tree(angle, 31.0f);
      if (mirrored)  // the limb leaves the trunk to the left
        for (int y = 0; y < mask.height(); ++y)
          std::reverse(&mask(0, y), &mask(0, y) + mask.width());
      for (const float downscale : {1.0f, 0.5f}) {
        perch::perch_options options;
        options.downscale = downscale;
        auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f},
                                       ws, options);
        REQUIRE(found);
        REQUIRE(found->outcome == perch_outcome::found);
        for (const perch::perch_site& site : found->sites) {
          const perch::window_measures& w = site.window;
          // Out along the limb, away from the trunk: 0° to the right, 180° to the left, up is +.
          const float expected = mirrored ? (angle >= 0 ? 180.0f - angle : -180.0f - angle) : angle;
          CHECK(std::abs(w.heading_deg - expected) < 3.0f);
          const float trunk_x = mirrored ? static_cast<float>(mask.width() - 1) - 160.0f : 160.0f;
          CHECK(std::abs(static_cast<float>(w.base_end.x) - trunk_x) <
                std::abs(static_cast<float>(w.tip_end.x) - trunk_x));
          // One drone width (90 px at 2 mm/px) apart, the perch between them.
          const float span = std::hypot(static_cast<float>(w.tip_end.x - w.base_end.x),
                                        static_cast<float>(w.tip_end.y - w.base_end.y));
          CHECK(span == doctest::Approx(90.0f).epsilon(0.06));
          CHECK(std::min(w.base_end.x, w.tip_end.x) <= w.centre.x);
          CHECK(w.centre.x <= std::max(w.base_end.x, w.tip_end.x));
          CHECK_FALSE(w.has_position);
        }
      }
    }
  }
}

TEST_CASE("find_perch: with depth, the branch's ends and axis in 3-D") {
  const auto mask = t_tree(0.0f, 31.0f);
  const perch::pinhole camera{1000.0f, 1000.0f, 320.0f, 240.0f};
  image<std::uint16_t> depth(mask.width(), mask.height());
  perch::workspace ws;
  // Fronto-parallel at 2 m: the level limb's axis is the camera's +x.
  perch::fill(depth.view(), std::uint16_t{2000});
  auto flat = perch::find_perch(mask.view(), perch::tendon_claw{},
                                perch::depth_scale{depth.view(), camera}, ws);
  REQUIRE(flat);
  REQUIRE(flat->outcome == perch_outcome::found);
  const perch::window_measures& f = flat->sites.front().window;
  REQUIRE(f.has_position);
  CHECK(f.axis_m.norm() == doctest::Approx(1.0f));
  CHECK(f.axis_m.x() == doctest::Approx(1.0f).epsilon(0.01));
  CHECK(f.base_end_m.z() == doctest::Approx(2.0f));
  CHECK(f.tip_end_m.x() - f.base_end_m.x() == doctest::Approx(0.18f).epsilon(0.06));
  // The limb recedes from the camera, 1 mm deeper per pixel to the right: its axis leans away.
  for (int y = 0; y < depth.height(); ++y)
    for (int x = 0; x < depth.width(); ++x) depth(x, y) = static_cast<std::uint16_t>(1800 + x);
  auto leaning = perch::find_perch(mask.view(), perch::tendon_claw{},
                                   perch::depth_scale{depth.view(), camera}, ws);
  REQUIRE(leaning);
  REQUIRE(leaning->outcome == perch_outcome::found);
  const perch::window_measures& l = leaning->sites.front().window;
  REQUIRE(l.has_position);
  CHECK(l.axis_m.norm() == doctest::Approx(1.0f));
  CHECK(l.tip_end_m.z() > l.base_end_m.z() + 0.02f);
  CHECK(l.axis_m.z() > 0.1f);
  CHECK(std::abs(l.axis_m.y()) < 0.02f);
}

TEST_CASE("find_perch: depth gives the scale and the 3-D position") {
  const auto mask = t_tree(0.0f, 31.0f);
  // A fronto-parallel tree 2 m away seen with f = 1000 px: 2 mm/px.
  image<std::uint16_t> depth(mask.width(), mask.height());
  perch::fill(depth.view(), std::uint16_t{2000});
  perch::depth_scale scale{depth.view(), {1000.0f, 1000.0f, 320.0f, 240.0f}};
  perch::workspace ws;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, scale, ws);
  REQUIRE(found);
  REQUIRE(found->outcome == perch_outcome::found);
  const auto& site = found->sites.front().window;
  CHECK(found->mm_per_px == doctest::Approx(2.0f));
  REQUIRE(site.has_position);
  CHECK(site.position_m.z() == doctest::Approx(2.0f));
  CHECK(site.position_m.x() ==
        doctest::Approx((static_cast<float>(site.centre.x) - 320.0f) * 2.0f / 1000.0f).epsilon(0.01));
  // All depth invalid: a clear status.
  perch::fill(depth.view(), std::uint16_t{0});
  auto none = perch::find_perch(mask.view(), perch::tendon_claw{}, scale, ws);
  REQUIRE_FALSE(none);
  CHECK(none.error().code == errc::no_valid_depth);
}

TEST_CASE("find_perch: every platform runs on the same tree") {
  const auto mask = t_tree(0.0f, 41.0f);
  perch::workspace ws;
  auto run = [&](const auto& platform) {
    auto found = perch::find_perch(mask.view(), platform, perch::fixed_scale{2.0f}, ws);
    REQUIRE(found);
    CHECK(found->platform == std::remove_cvref_t<decltype(platform)>::name);
    CHECK(found->rejections.size() ==
          perch::leaf_count<std::remove_cvref_t<decltype(platform.constraints)>>);
    return found->outcome;
  };
  CHECK(run(perch::tendon_claw{}) == perch_outcome::found);
  CHECK(run(perch::tensile_tether{}) != perch_outcome::no_tree);
  CHECK(run(perch::metamorphic_quadrotor{}) != perch_outcome::no_tree);
  CHECK(run(perch::ornithopter{}) != perch_outcome::no_tree);
  // The treecreeper wants the vertical trunk, which is too short here for its window but is
  // vertical: every rejection is on a stated constraint.
  CHECK(run(perch::treecreeper{}) != perch_outcome::no_tree);
}

TEST_CASE("find_perch: stage timings come from the caller's clock") {
  const auto mask = t_tree(0.0f, 31.0f);
  perch::workspace ws;
  perch::perch_options options;
  options.clock = [] () noexcept -> std::int64_t {
    static std::int64_t t = 0;
    return t += 1'000'000;  // 1 ms per reading
  };
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws, options);
  REQUIRE(found);
  CHECK(found->timing.distance_ms == doctest::Approx(1.0f));
  CHECK(found->timing.bridge_ms == doctest::Approx(1.0f));  // one lap, nothing to bridge
  CHECK(found->timing.total_ms == doctest::Approx(8.0f));
  options.clock = nullptr;
  auto untimed = perch::find_perch(mask.view(), ws, options);
  REQUIRE(untimed);
  CHECK(untimed->timing.total_ms == 0.0f);
}

TEST_CASE("find_perch: bad input gets a status, never a crash") {
  perch::workspace ws;
  const auto mask = t_tree(0.0f, 31.0f);
  perch::image_view<const std::uint8_t> null_view(nullptr, 10, 10);
  CHECK(perch::find_perch(null_view, ws).error().code == errc::null_data);
  perch::image_view<const std::uint8_t> short_stride(mask.data(), 10, 10, 5);
  CHECK(perch::find_perch(short_stride, ws).error().code == errc::stride_too_small);
  perch::image_view<const std::uint8_t> empty(mask.data(), 0, 10);
  CHECK(perch::find_perch(empty, ws).error().code == errc::empty_image);

  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (const float bad : {nan, 0.0f, -1.0f, std::numeric_limits<float>::infinity()}) {
    CAPTURE(bad);
    CHECK(perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{bad}, ws)
              .error().code == errc::invalid_parameter);
    perch::perch_options o;
    o.stride_mm = bad;
    CHECK(perch::find_perch(mask.view(), ws, o).error().code == errc::invalid_parameter);
    perch::tendon_claw claw;
    claw.geometry.drone_width_mm = bad;
    CHECK(perch::find_perch(mask.view(), claw, perch::trunk_prior{}, ws).error().code ==
          errc::invalid_parameter);
    perch::tendon_claw narrow_claw;
    narrow_claw.geometry.claw_width_mm = bad;
    CHECK(perch::find_perch(mask.view(), narrow_claw, perch::trunk_prior{}, ws).error().code ==
          errc::invalid_parameter);
    CHECK(perch::find_perch(mask.view(), perch::tendon_claw{}, perch::trunk_prior{bad}, ws)
              .error().code == errc::invalid_parameter);
    perch::perch_options reduce;
    reduce.downscale = bad;
    CHECK(perch::find_perch(mask.view(), ws, reduce).error().code == errc::invalid_parameter);
    perch::image<std::uint16_t> depth_mm(mask.width(), mask.height(), 2000);
    perch::depth_scale lens{depth_mm.view(), {bad, 500.0f, 320.0f, 240.0f}};
    CHECK(perch::find_perch(mask.view(), perch::tendon_claw{}, lens, ws).error().code ==
          errc::invalid_parameter);
  }
  perch::perch_options enlarge;
  enlarge.downscale = 1.5f;
  CHECK(perch::find_perch(mask.view(), ws, enlarge).error().code == errc::invalid_parameter);
  // The pruning's diameter range is the platform's: another is refused, not overwritten.
  perch::perch_options own_range;
  own_range.pruning.diameter_min_mm = 10.0f;
  CHECK(perch::find_perch(mask.view(), ws, own_range).error().code == errc::invalid_parameter);
  perch::perch_options bad_pruning;
  bad_pruning.pruning.alpha = 2.0f;
  CHECK(perch::find_perch(mask.view(), ws, bad_pruning).error().code == errc::invalid_parameter);
  // Dimensions: negative, more than 2^30 pixels, a stride whose product with the height overflows.
  const int huge = std::numeric_limits<int>::max();
  CHECK(perch::find_perch(perch::image_view<const std::uint8_t>(mask.data(), -1, 10), ws)
            .error().code == errc::bad_dimensions);
  CHECK(perch::find_perch(perch::image_view<const std::uint8_t>(mask.data(), huge, huge), ws)
            .error().code == errc::image_too_large);
  CHECK(perch::find_perch(perch::image_view<const std::uint8_t>(mask.data(), 32769, 32768), ws)
            .error().code == errc::image_too_large);
  CHECK(perch::find_perch(perch::image_view<const std::uint8_t>(
                              mask.data(), 4, huge, std::numeric_limits<std::ptrdiff_t>::max() / 4),
                          ws)
            .error().code == errc::size_overflow);
  perch::perch_options roll;
  roll.camera.roll_deg = nan;
  CHECK(perch::find_perch(mask.view(), ws, roll).error().code == errc::invalid_parameter);
  roll.camera.roll_deg = std::numeric_limits<float>::infinity();
  CHECK(perch::find_perch(mask.view(), ws, roll).error().code == errc::invalid_parameter);
  perch::tendon_claw inverted;
  inverted.geometry.grasp_min_mm = 200.0f;
  CHECK(perch::find_perch(mask.view(), inverted, perch::trunk_prior{}, ws).error().code ==
        errc::range_inverted);
  perch::tendon_claw weights;
  weights.scorer.lambda_slope = 0.5f;
  CHECK(perch::find_perch(mask.view(), weights, perch::trunk_prior{}, ws).error().code ==
        errc::weights_not_normalised);
  perch::image<std::uint16_t> small_depth(10, 10);
  perch::depth_scale depth{small_depth.view(), {500.0f, 500.0f, 5.0f, 5.0f}};
  CHECK(perch::find_perch(mask.view(), perch::tendon_claw{}, depth, ws).error().code ==
        errc::size_mismatch);
  // Downscaled, the depth view is checked before it is resampled: a null one used to be read
  // (a crash), and one a column narrower than the mask reduced to the mask's reduced size.
  perch::perch_options half;
  half.downscale = 0.5f;
  const perch::pinhole lens{500.0f, 500.0f, 320.0f, 240.0f};
  perch::depth_scale null_depth{
      perch::image_view<const std::uint16_t>(nullptr, mask.width(), mask.height()), lens};
  CHECK(perch::find_perch(mask.view(), perch::tendon_claw{}, null_depth, ws, half).error().code ==
        errc::null_data);
  perch::image<std::uint16_t> narrow_depth(mask.width() - 1, mask.height(), 2000);
  perch::depth_scale narrow{narrow_depth.view(), lens};
  CHECK(perch::find_perch(mask.view(), perch::tendon_claw{}, narrow, ws, half).error().code ==
        errc::size_mismatch);
  perch::depth_scale short_stride_depth{
      perch::image_view<const std::uint16_t>(narrow_depth.data(), mask.width(), mask.height(), 8),
      lens};
  CHECK(perch::find_perch(mask.view(), perch::tendon_claw{}, short_stride_depth, ws, half)
            .error().code == errc::stride_too_small);
  perch::tendon_claw no_weights;
  no_weights.scorer.lambda_slope = 0.0f;
  no_weights.scorer.lambda_diameter = 0.0f;
  CHECK(perch::find_perch(mask.view(), no_weights, perch::trunk_prior{}, ws).error().code ==
        errc::weights_not_normalised);
  perch::perch_options few;
  few.limits.windows = 2;
  const auto too_many = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws, few);
  REQUIRE_FALSE(too_many);
  CHECK(too_many.error().code == errc::capacity_exceeded);
  CHECK(too_many.error().detail == "perch_options.limits.windows");
}

namespace {

/// Checks what every result must satisfy: sites inside the image, on the mask (at full
/// resolution), with finite values; near misses inside the image.
void check_sites(const image<std::uint8_t>& mask, const perch::perch_result& r, float downscale) {
  for (const perch::perch_site& s : r.sites) {
    const perch::window_measures& m = s.window;
    CAPTURE(m.centre.x);
    CAPTURE(m.centre.y);
    REQUIRE(mask.view().contains(m.centre.x, m.centre.y));
    if (downscale == 1.0f) CHECK(mask(m.centre.x, m.centre.y) != 0);
    for (const float v : {s.penalty, m.slope_deg, m.claw_diameter_mm, m.curvature_max_per_mm})
      CHECK(std::isfinite(v));
  }
  for (const perch::near_miss& m : r.near_misses)
    if (m.present) CHECK(mask.view().contains(m.window.centre.x, m.window.centre.y));
}

image<std::uint8_t> mask_where(int width, int height, auto&& tree) {
  image<std::uint8_t> m(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) m(x, y) = tree(x, y) ? 255 : 0;
  return m;
}

}  // namespace

TEST_CASE("find_perch: degenerate masks are outcomes with valid sites, never errors") {
  perch::workspace ws;
  struct degenerate {
    std::string name;
    image<std::uint8_t> mask;
  };
  const degenerate cases[] = {
      {"1x1 tree", image<std::uint8_t>(1, 1, 255)},
      {"1xN tree", image<std::uint8_t>(200, 1, 255)},
      {"Nx1 tree", image<std::uint8_t>(1, 200, 255)},
      {"all foreground", image<std::uint8_t>(64, 48, 255)},
      {"one pixel", mask_where(64, 48, [](int x, int y) { return x == 30 && y == 20; })},
      {"checkerboard", mask_where(64, 48, [](int x, int y) { return (x + y) % 2 == 1; })},
      {"every border", mask_where(300, 200, [](int x, int y) {
         return x < 12 || y < 12 || x >= 288 || y >= 188 || std::abs(x - 150) < 8 ||
                std::abs(y - 100) < 6;
       })},
  };
  for (const degenerate& c : cases)
    for (const float downscale : {1.0f, 0.5f}) {
      CAPTURE(c.name);
      CAPTURE(downscale);
      perch::perch_options options;
      options.downscale = downscale;
      // Area downscaling by 0.5 leaves a quarter of a lone pixel: below half, no tree.
      const bool vanishes = c.name == "one pixel" && downscale < 1.0f;
      auto trunk = perch::find_perch(c.mask.view(), ws, options);
      REQUIRE(trunk);
      CHECK((trunk->outcome == perch_outcome::no_tree) == vanishes);
      check_sites(c.mask, *trunk, downscale);
      auto fixed = perch::find_perch(c.mask.view(), perch::tendon_claw{}, perch::fixed_scale{5.0f},
                                     ws, options);
      REQUIRE(fixed);
      CHECK((fixed->outcome == perch_outcome::no_tree) == vanishes);
      check_sites(c.mask, *fixed, downscale);
    }
  // The trunk prior makes a tree of one width 180 mm wide, too thick for the claw; the frame
  // touching every border has 12 px limbs (60 mm at 5 mm/px) and a perch.
  CHECK(perch::find_perch(cases[1].mask.view(), ws)->outcome == perch_outcome::no_perch);
  CHECK(perch::find_perch(cases[3].mask.view(), ws)->outcome == perch_outcome::no_perch);
  auto frame = perch::find_perch(cases[6].mask.view(), perch::tendon_claw{},
                                 perch::fixed_scale{5.0f}, ws);
  REQUIRE(frame);
  CHECK(frame->outcome == perch_outcome::found);
  image<std::uint8_t> empty_pixel(1, 1, 0);
  CHECK(perch::find_perch(empty_pixel.view(), ws)->outcome == perch_outcome::no_tree);
}

/// The claw without the rules about the frame's edge and detached pieces, to check where sites
/// on the frame's last row are reported (the stock claw never perches there).
struct claw_at_any_border {
  static constexpr std::string_view name = "claw-at-any-border";
  perch::platform_geometry geometry{};
  perch::all_of<perch::diameter_range, perch::max_slope> constraints{};
  perch::pli_penalty scorer{};
};

/// The tensile tether's grasp range and slope without the rules about the frame's edge, detached
/// pieces and resolution (every stock platform has them).
struct tether_at_any_border {
  static constexpr std::string_view name = "tether-at-any-border";
  perch::platform_geometry geometry = perch::tensile_tether{}.geometry;
  perch::all_of<perch::diameter_range, perch::max_slope> constraints{
      perch::diameter_range{geometry.grasp_min_mm, geometry.grasp_max_mm},
      perch::max_slope{perch::tensile_tether::max_slope_deg}};
  perch::pli_penalty scorer{.slope_max_deg = perch::tensile_tether::max_slope_deg,
                            .diameter_min_mm = geometry.grasp_min_mm,
                            .diameter_max_mm = geometry.grasp_max_mm,
                            .ideal_diameter_mm = geometry.grasp_min_mm};
};

TEST_CASE("find_perch: downscaled sites on an odd-sized mask's last row stay in the image") {
  // Fuzz finding (tests/fuzz/corpus/fuzz_find_perch/odd-height-downscale-site-outside): at
  // downscale 0.5 the last reduced row of an odd-height mask is centred half a pixel below the
  // image, and sites there were reported at y = height.
  perch::workspace ws;
  perch::perch_options half;
  half.downscale = 0.5f;
  for (const int height : {1, 5, 41}) {
    CAPTURE(height);
    const auto bar = mask_where(120, height, [&](int, int y) { return y == height - 1; });
    CHECK(perch::find_perch(bar.view(), perch::tendon_claw{}, perch::fixed_scale{30.0f}, ws, half)
              ->outcome == perch_outcome::no_perch);  // on the frame's edge
    auto found = perch::find_perch(bar.view(), claw_at_any_border{}, perch::fixed_scale{30.0f},
                                   ws, half);
    REQUIRE(found);
    REQUIRE(found->outcome == perch_outcome::found);
    check_sites(bar, *found, half.downscale);
    CHECK(found->sites.front().window.centre.y == height - 1);
  }
  // The fuzzer's input, decoded as tests/fuzz/fuzz_find_perch.cpp does: a 58 × 1 mask.
  const std::uint8_t bits[] = {0x0, 0x0, 0x0, 0xfd, 0xff, 0xfc, 0xe0, 0x7, 0x52, 0x0, 0x0};
  image<std::uint8_t> row(58, 1);
  for (int i = 0; i < 58; ++i) row(i, 0) = (bits[i / 8] >> (i % 8)) & 1;
  perch::perch_options fuzzed = half;
  fuzzed.stride_mm = 0.25f + 182.0f / 16.0f;
  fuzzed.ranking.top_k = 5;
  for (const float trunk_mm : {107.5f, 60.0f}) {
    auto found = perch::find_perch(row.view(), perch::tendon_claw{}, perch::trunk_prior{trunk_mm},
                                   ws, fuzzed);
    REQUIRE(found);
    check_sites(row, *found, half.downscale);
  }
  auto tether = perch::find_perch(row.view(), tether_at_any_border{}, perch::fixed_scale{20.0f}, ws,
                                  half);
  REQUIRE(tether);
  CHECK(tether->outcome == perch_outcome::found);
  check_sites(row, *tether, half.downscale);
}

TEST_CASE("find_perch: a borrowed workspace too small says how many bytes it needs") {
  const auto mask = t_tree(0.0f, 31.0f);
  std::vector<std::byte> tiny(4096);
  perch::workspace borrowed{std::span<std::byte>(tiny)};
  auto failed = perch::find_perch(mask.view(), borrowed);
  REQUIRE_FALSE(failed);
  CHECK(failed.error().code == errc::workspace_too_small);
  CHECK(failed.error().needed > tiny.size());
  // Sizes and options find_perch rejects before taking memory need none (no overflow, no UB).
  const int huge = std::numeric_limits<int>::max();
  CHECK(perch::find_perch_workspace_bytes(huge, 1) == 0);
  CHECK(perch::find_perch_workspace_bytes(huge, huge) == 0);
  CHECK(perch::find_perch_workspace_bytes(32769, 32768) == 0);
  CHECK(perch::find_perch_workspace_bytes(-5, 10) == 0);
  CHECK(perch::find_perch_workspace_bytes(0, 10) == 0);
  perch::perch_options nan_downscale;
  nan_downscale.downscale = std::numeric_limits<float>::quiet_NaN();
  CHECK(perch::find_perch_workspace_bytes(640, 480, nan_downscale) == 0);
  CHECK(perch::find_perch_workspace_bytes(32768, 32768) > perch::find_perch_workspace_bytes(640, 480));
  // The size query is enough.
  std::vector<std::byte> enough(perch::find_perch_workspace_bytes(mask.width(), mask.height()));
  perch::workspace sized{std::span<std::byte>(enough)};
  perch::test::allocation_scope scope;
  auto found = perch::find_perch(mask.view(), sized);
  CHECK(scope.count() == 0);
  REQUIRE(found);
  CHECK(found->outcome == perch_outcome::found);
}

namespace {

/// Windows `constraint` rejected (first failed, in the platform's order).
std::uint32_t rejected_by(const perch::perch_result& r, std::string_view constraint) {
  for (const perch::rejection_count& c : r.rejections)
    if (c.constraint == constraint) return c.windows;
  return 0;
}

/// The window's centreline points in input pixels.
std::vector<perch::point2f> window_points(const perch::perch_result& r, const perch::window_measures& w) {
  std::vector<perch::point2f> out;
  const perch::skeleton_limb& limb = r.limbs[static_cast<std::size_t>(w.limb)];
  for (std::uint32_t i = w.first; i <= w.last; ++i)
    out.push_back(r.mask.to_input(perch::to_point(limb.points[i]) +
                                  perch::to_point(r.mask.offset)));
  return out;
}

}  // namespace

TEST_CASE("find_perch: a site keeps the claw's reach clear of a thick side limb") {
  // The T tree's limb (31 px = 62 mm) with a 19 px (38 mm) limb rising from it at x = 400:
  // every point of a site's window is at least 70 mm (35 px) from the side limb's surface,
  // beyond its own surface (15.5 px), give or take a pixel.
  auto mask = t_tree(0.0f, 31.0f);
  capsule(mask, {400, 260}, {400, 60}, 9.5f);
  perch::workspace ws;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(found);
  CHECK(rejected_by(*found, "clearance") > 0);
  bool on_limb = false;
  for (const perch::perch_site& site : found->sites) {
    for (const perch::point2f& p : window_points(*found, site.window)) {
      if (std::abs(p.y() - 260) > 5) continue;  // the side limb's own windows: above the limb
      on_limb = true;
      CAPTURE(p.x());
      CHECK(std::abs(p.x() - 400) - 9.5f - 15.5f >= 35.0f - 1.0f);
    }
  }
  CHECK(found->outcome == perch_outcome::found);
  CHECK(on_limb);
  const std::uint32_t crowded = rejected_by(*found, "clearance");
  // Without the side limb only the windows next to the trunk are too close to another limb.
  const auto plain = t_tree(0.0f, 31.0f);
  auto open = perch::find_perch(plain.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(open);
  CHECK(rejected_by(*open, "clearance") + 5 < crowded);
}

TEST_CASE("find_perch: a detached fragment is never a perch, however attractive") {
  // The T tree, and a level bar of 19 px (38 mm: thinner, so preferred by the scorer over the
  // limb's 62 mm) floating well above the limb, connected to nothing.
  auto mask = t_tree(0.0f, 31.0f);
  capsule(mask, {300, 60}, {620, 60}, 9.5f);
  perch::workspace ws;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(found);
  REQUIRE(found->outcome == perch_outcome::found);
  CHECK(rejected_by(*found, "supported") > 0);
  for (const perch::perch_site& site : found->sites) {
    CAPTURE(site.window.centre.y);
    CHECK(site.window.grounded);
    CHECK(std::abs(site.window.centre.y - 60) > 20);
  }
  CHECK(std::abs(found->sites.front().window.centre.y - 260) <= 2);
  // The same bar touching the bottom of the frame (a second stem) is a perch.
  image<std::uint8_t> grounded_bar(640, 480);
  capsule(grounded_bar, {300, 60}, {620, 60}, 9.5f);
  capsule(grounded_bar, {620, 60}, {620, 520}, 20.0f);
  auto stem = perch::find_perch(grounded_bar.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(stem);
  REQUIRE(stem->outcome == perch_outcome::found);
  CHECK(std::abs(stem->sites.front().window.centre.y - 60) <= 2);
}

TEST_CASE("find_perch: no window's outline comes within 3 px of the frame's edge") {
  // The T tree's limb runs out of the right edge of a 480 px wide frame.
  const auto mask = t_tree(0.0f, 31.0f, 480, 480);
  perch::workspace ws;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(found);
  CHECK(rejected_by(*found, "border") > 0);
  REQUIRE(found->outcome == perch_outcome::found);
  for (const perch::perch_site& site : found->sites) {
    CHECK(site.window.border_px >= 3.0f);
    for (const perch::point2f& p : window_points(*found, site.window))
      CHECK(p.x() + 15.5f <= 479.0f - 3.0f + 1.0f);
  }
}

TEST_CASE("find_perch: no site's window spans a 30 degree kink") {
  // The T tree's limb level for 170 px from the trunk's surface, then turning 30° upward.
  image<std::uint8_t> mask(640, 480);
  capsule(mask, {160, 520}, {160, 120}, 45);
  const perch::point2f kink(375, 260);
  capsule(mask, {160, 260}, kink, 15.5f);
  const float a = 30.0f * std::numbers::pi_v<float> / 180.0f;
  capsule(mask, kink, kink + 240.0f * perch::point2f(std::cos(a), -std::sin(a)), 15.5f);
  perch::workspace ws;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(found);
  CHECK(rejected_by(*found, "bend") > 0);
  CHECK(found->outcome == perch_outcome::found);  // on either leg, clear of the kink
  for (const perch::perch_site& site : found->sites) {
    const auto points = window_points(*found, site.window);
    float nearest = 1e9f;
    for (const perch::point2f& p : points) nearest = std::min(nearest, (p - kink).norm());
    CAPTURE(site.window.centre.x);
    CHECK(site.window.bend_deg <= 20.0f);
    // The window does not reach over the kink: it stays on one leg, clear of the turn.
    CHECK(!(points.front().x() < kink.x() - 5 && points.back().x() > kink.x() + 5));
    CHECK(!(points.back().x() < kink.x() - 5 && points.front().x() > kink.x() + 5));
    CHECK(nearest > 10.0f);
  }
}

TEST_CASE("find_perch: no site's window holds a second limb fused along its limb") {
  // The T tree's limb (31 px = 62 mm), and a 20 px (40 mm) limb lying along its top for 60 px,
  // the two outlines 2 px into each other: one band 49 px wide there, 98 mm, still inside the
  // claw's range, and the skeleton runs through it as one limb. The claw closing there would
  // close on both limbs: no window reaches into the fused stretch (x 450..510).
  image<std::uint8_t> mask(900, 480);
  capsule(mask, {160, 520}, {160, 120}, 45);
  capsule(mask, {160, 260}, {840, 260}, 15.5f);
  capsule(mask, {450, 236.5f}, {510, 236.5f}, 10.0f);
  perch::workspace ws;
  perch::perch_options options;
  options.ranking.top_k = 50;
  auto found = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws,
                                 options);
  REQUIRE(found);
  CHECK(rejected_by(*found, "one_limb") > 0);
  REQUIRE(found->outcome == perch_outcome::found);
  bool before = false, after = false;
  for (const perch::perch_site& site : found->sites) {
    const auto points = window_points(*found, site.window);
    CAPTURE(site.window.centre.x);
    for (const perch::point2f& p : points) CHECK((p.x() < 450.0f || p.x() > 510.0f));
    before = before || site.window.centre.x < 450;
    after = after || site.window.centre.x > 510;
  }
  CHECK(before);  // the limb either side of the fused stretch is still a perch
  CHECK(after);
}

TEST_CASE("find_perch: a scale known to ±20 % holds each rule at both ends of the range") {
  // The T tree's limb 19 px wide at 2 mm/px: 38 mm, graspable when the scale is known; at the
  // fine end of ±20 % it may be 30.4 mm, 1.6 px from the grasp minimum's 2.5 px margin.
  const auto mask = t_tree(0.0f, 19.0f);
  perch::workspace ws;
  auto known = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws);
  REQUIRE(known);
  CHECK(known->outcome == perch_outcome::found);
  auto uncertain = perch::find_perch(mask.view(), perch::tendon_claw{},
                                     perch::fixed_scale{2.0f, 0.2f}, ws);
  REQUIRE(uncertain);
  CHECK(uncertain->outcome == perch_outcome::no_perch);
  CHECK(rejected_by(*uncertain, "resolution") + rejected_by(*uncertain, "diameter") > 0);
  CHECK(uncertain->mm_per_px == doctest::Approx(2.0f));  // the scale itself is reported as given
  // The trunk prior takes the same uncertainty; a bad one is a status.
  auto prior = perch::find_perch(mask.view(), perch::tendon_claw{}, perch::trunk_prior{180.0f, 0.6f},
                                 ws);
  REQUIRE(!prior);
  CHECK(prior.error().code == errc::invalid_parameter);
}
