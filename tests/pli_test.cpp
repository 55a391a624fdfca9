#include "perch/pli.hpp"

#include <doctest/doctest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <cstdint>
#include <limits>
#include <vector>

#include "allocation_counter.hpp"
#include "perch/core/image.hpp"

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
  CHECK(found->timing.total_ms == doctest::Approx(7.0f));
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
  }
  perch::perch_options roll;
  roll.camera.roll_deg = nan;
  CHECK_FALSE(perch::find_perch(mask.view(), ws, roll));
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
  perch::perch_options few;
  few.max_windows = 2;
  CHECK(perch::find_perch(mask.view(), perch::tendon_claw{}, perch::fixed_scale{2.0f}, ws, few)
            .error().code == errc::capacity_exceeded);
}

TEST_CASE("find_perch: a borrowed workspace too small says how many bytes it needs") {
  const auto mask = t_tree(0.0f, 31.0f);
  std::vector<std::byte> tiny(4096);
  perch::workspace borrowed{std::span<std::byte>(tiny)};
  auto failed = perch::find_perch(mask.view(), borrowed);
  REQUIRE_FALSE(failed);
  CHECK(failed.error().code == errc::workspace_too_small);
  CHECK(failed.error().needed > tiny.size());
  // The size query is enough.
  std::vector<std::byte> enough(perch::find_perch_workspace_bytes(mask.width(), mask.height()));
  perch::workspace sized{std::span<std::byte>(enough)};
  perch::test::allocation_scope scope;
  auto found = perch::find_perch(mask.view(), sized);
  CHECK(scope.count() == 0);
  REQUIRE(found);
  CHECK(found->outcome == perch_outcome::found);
}
