// SPDX-License-Identifier: BSL-1.0
#include "perch/policy/constraints.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include "perch/core/disc_index.hpp"
#include "perch/core/image.hpp"

using perch::errc;

namespace {
perch::window_measures window(float slope_deg, float diameter_mm) {
  perch::window_measures m;
  m.slope_deg = slope_deg;
  m.claw_diameter_mm = diameter_mm;
  m.mm_per_px = 1.0f;
  return m;
}
}  // namespace

TEST_CASE("constraints: misses are measured in the constraint's unit, 0 when passing") {
  const perch::diameter_range d{30.0f, 110.0f, 0.0f};  // the paper's plain range
  CHECK(d(window(0, 50)) == 0.0f);
  CHECK(d(window(0, 25)) == doctest::Approx(5.0f));
  CHECK(d(window(0, 130)) == doctest::Approx(20.0f));
  CHECK(d(window(0, std::nanf(""))) != 0.0f);  // NaN never passes silently... it is not <= 0
  const perch::max_slope s{35.0f};
  CHECK(s(window(35, 50)) == 0.0f);
  CHECK(s(window(40, 50)) == doctest::Approx(5.0f));
  const perch::min_slope v{70.0f};
  CHECK(v(window(65, 50)) == doctest::Approx(5.0f));
  CHECK(v(window(80, 50)) == 0.0f);
  perch::window_measures bent = window(0, 50);
  bent.curvature_max_per_mm = 0.01f;
  CHECK(perch::max_curvature{.max_per_mm = 0.005f}(bent) == doctest::Approx(0.005f));
  bent.reversal_mm = 12.0f;
  CHECK(perch::monotonic{.tolerance_mm = 5.0f}(bent) == doctest::Approx(7.0f));
}

TEST_CASE("constraints: the diameter margin is in pixels at the window's scale") {
  const perch::diameter_range d{30.0f, 110.0f};  // default margin: half a pixel
  CHECK(d.margin_px == 0.5f);
  CHECK(d(window(0, 50)) == 0.0f);
  CHECK(d(window(0, 30.5f)) == 0.0f);                            // 1 mm/px: 30.5 is enough
  CHECK(d(window(0, 30.2f)) == doctest::Approx(0.3f));           // within noise of 30
  CHECK(d(window(0, 109.6f)) == doctest::Approx(0.1f));          // within noise of 110
  perch::window_measures coarse = window(0, 31.0f);
  coarse.mm_per_px = 4.0f;                                       // half a pixel is 2 mm
  CHECK(d(coarse) == doctest::Approx(1.0f));
  CHECK(perch::diameter_range{30.0f, 110.0f, -1.0f}.validate().error().code ==
        errc::invalid_parameter);
}

TEST_CASE("constraints: the window's lower-tercile diameter guards the minimum on rough outlines") {
  const perch::diameter_range d{30.0f, 110.0f};  // low margin: a quarter pixel
  CHECK(d.low_margin_px == 0.25f);
  perch::window_measures rough = window(0, 33.0f);  // the mean passes by 2.5 px ...
  rough.diameter_low_mm = 29.0f;                     // ... but a third of the window reads < 29
  CHECK(d(rough) == doctest::Approx(1.25f));
  rough.diameter_low_mm = 30.25f;  // exactly min + a quarter pixel
  CHECK(d(rough) == 0.0f);
  rough.diameter_low_mm = 0.0f;  // not measured: the mean's test alone
  CHECK(d(rough) == 0.0f);
  perch::diameter_range plain{30.0f, 110.0f, 0.0f, -1.0f};  // off
  rough.diameter_low_mm = 20.0f;
  CHECK(plain(rough) == 0.0f);
  CHECK(plain.validate());
  CHECK(perch::diameter_range{30.0f, 110.0f, 0.5f, std::nanf("")}.validate().error().code ==
        errc::invalid_parameter);
}

TEST_CASE("constraints: bending stress of paper eq. 4 (1.5 kg, r = 15 mm, L = 2 m -> 11.1 MPa)") {
  CHECK(perch::bending_stress_mpa(1.5f, 15.0f, 2000.0f) == doctest::Approx(11.1f).epsilon(0.005));
  perch::window_measures m = window(0, 30.0f);  // r = 15 mm
  m.origin_horizontal_mm = 2000.0f;
  CHECK(perch::bending_stress{.mass_kg = 1.5f}(m) == 0.0f);  // 11.1 <= 27 / 2
  m.origin_horizontal_mm = 6000.0f;                          // 33.3 MPa
  CHECK(perch::bending_stress{.mass_kg = 1.5f}(m) == doctest::Approx(33.3f - 13.5f).epsilon(0.01));
  CHECK(perch::bending_stress{.mass_kg = 1.5f, .load_factor = 3.0f}(window(0, 30.0f)) == 0.0f);
}

TEST_CASE("constraints: parameters are validated with named statuses") {
  CHECK(perch::diameter_range{30.0f, 110.0f}.validate());
  CHECK(perch::diameter_range{110.0f, 30.0f}.validate().error().code == errc::range_inverted);
  CHECK(perch::diameter_range{std::nanf(""), 30.0f}.validate().error().code ==
        errc::invalid_parameter);
  CHECK(!perch::max_slope{-1.0f}.validate());
  CHECK(!perch::max_slope{std::numeric_limits<float>::infinity()}.validate());
  CHECK(!perch::max_curvature{0.0f}.validate());
  CHECK(!perch::bending_stress{.mass_kg = 0.0f}.validate());
  CHECK(!perch::free_circle{.radius_mm = -3.0f}.validate());
  CHECK(!perch::free_space_above{.width_mm = std::nanf("")}.validate());
  CHECK(!perch::clearance{.margin_mm = -1.0f}.validate());
}

TEST_CASE("constraints: resolved_diameter needs the diameter in range give or take a pixel") {
  const perch::resolved_diameter r{30.0f, 110.0f, 1.0f};
  CHECK(r.name == "resolution");
  CHECK(r.unit == "px");
  perch::window_measures m = window(0, 40.0f);
  m.mm_per_px = 2.0f;  // 20 px: 15 px + 1 is enough
  CHECK(r(m) == 0.0f);
  m.claw_diameter_mm = 31.0f;  // 15.5 px: half a pixel short of 15 + 1
  CHECK(r(m) == doctest::Approx(0.5f));
  m.claw_diameter_mm = 32.0f;  // exactly 16 px
  CHECK(r(m) == 0.0f);
  m.claw_diameter_mm = 109.5f;  // 54.75 px + 1 is 0.75 px past 55
  CHECK(r(m) == doctest::Approx(0.75f));
  m.claw_diameter_mm = 108.0f;
  CHECK(r(m) == 0.0f);
  // In pixels at the window's scale: 31 mm at 0.5 mm/px is 62 px, 2 px clear of 60 + 1.
  m.claw_diameter_mm = 31.0f;
  m.mm_per_px = 0.5f;
  CHECK(r(m) == 0.0f);
  m.mm_per_px = 4.0f;  // 7.75 px against 7.5 + 1
  CHECK(r(m) == doctest::Approx(0.75f));
  // Out of the range itself: diameter_range's to report, not this one's.
  m.mm_per_px = 2.0f;
  for (const float d : {10.0f, 29.9f, 110.1f, 300.0f}) {
    m.claw_diameter_mm = d;
    CAPTURE(d);
    CHECK(r(m) == 0.0f);
    CHECK(perch::diameter_range{30.0f, 110.0f, 0.0f}(m) > 0.0f);
  }
  // No scale: not known to fit.
  m.claw_diameter_mm = 50.0f;
  m.mm_per_px = 0.0f;
  CHECK(r(m) == 1.0f);
  m.mm_per_px = std::nanf("");
  CHECK(r(m) == 1.0f);
  // The lower tercile, where measured, is the diameter the minimum is held against.
  m.mm_per_px = 2.0f;
  m.claw_diameter_mm = 40.0f;
  m.diameter_low_mm = 31.0f;  // 15.5 px
  CHECK(r(m) == doctest::Approx(0.5f));
  m.diameter_low_mm = 60.0f;  // above the mean: the mean
  CHECK(r(m) == 0.0f);
  // Validation.
  CHECK(r.validate());
  CHECK(perch::resolved_diameter{110.0f, 30.0f, 1.0f}.validate().error().code ==
        errc::range_inverted);
  CHECK(perch::resolved_diameter{std::nanf(""), 110.0f, 1.0f}.validate().error().code ==
        errc::invalid_parameter);
  CHECK(perch::resolved_diameter{30.0f, 110.0f, -1.0f}.validate().error().code ==
        errc::invalid_parameter);
  CHECK(perch::resolved_diameter{30.0f, std::numeric_limits<float>::infinity(), 1.0f}
            .validate()
            .error()
            .code == errc::invalid_parameter);
}

TEST_CASE("constraints: max_slope reads the steepest tangent, max_bend the bend") {
  perch::window_measures m = window(10.0f, 50.0f);
  m.slope_max_deg = 40.0f;  // level on average, steep at one end
  CHECK(perch::max_slope{35.0f}(m) == doctest::Approx(5.0f));
  m.slope_max_deg = 20.0f;
  CHECK(perch::max_slope{35.0f}(m) == 0.0f);
  m.slope_deg = 38.0f;  // the chord still counts
  CHECK(perch::max_slope{35.0f}(m) == doctest::Approx(3.0f));

  const perch::max_bend bend{20.0f};
  CHECK(bend.name == "bend");
  CHECK(bend.unit == "deg");
  m.bend_deg = 20.0f;
  CHECK(bend(m) == 0.0f);
  m.bend_deg = 32.5f;
  CHECK(bend(m) == doctest::Approx(12.5f));
  CHECK(perch::max_bend{}(m) == doctest::Approx(12.5f));  // default 20°
  CHECK(bend.validate());
  CHECK(perch::max_bend{180.0f}.validate());
  CHECK(perch::max_bend{-1.0f}.validate().error().code == errc::invalid_parameter);
  CHECK(perch::max_bend{181.0f}.validate().error().code == errc::invalid_parameter);
  CHECK(perch::max_bend{std::nanf("")}.validate().error().code == errc::invalid_parameter);
}

TEST_CASE("constraints: image_border and supported") {
  const perch::image_border border{3.0f};
  CHECK(border.name == "border");
  CHECK(border.unit == "px");
  perch::window_measures m = window(0, 50);
  CHECK(border(m) == 0.0f);  // not measured: the largest float
  m.border_px = 3.0f;
  CHECK(border(m) == 0.0f);
  m.border_px = 1.0f;
  CHECK(border(m) == doctest::Approx(2.0f));
  m.border_px = -4.5f;  // the outline runs out of the frame
  CHECK(border(m) == doctest::Approx(7.5f));
  m.border_px = 10.0f;
  CHECK(border(m) == 0.0f);
  CHECK(perch::image_border{}.margin_px == 3.0f);
  CHECK(border.validate());
  CHECK(perch::image_border{-1.0f}.validate().error().code == errc::invalid_parameter);
  CHECK(perch::image_border{std::nanf("")}.validate().error().code == errc::invalid_parameter);

  const perch::supported held{};
  CHECK(held.name == "supported");
  perch::window_measures w = window(0, 50);
  CHECK(w.grounded);  // the default: grounded
  CHECK(held(w) == 0.0f);
  w.grounded = false;
  CHECK(held(w) == 1.0f);
  CHECK(held.validate());
}

TEST_CASE("constraints: clearance in mm from other limbs' surfaces over the window's points") {
  // A limb along row 50 (x = 10 … 50, radius 5.5: 5 px to its outline) and another limb's disc
  // of radius 10 at (30, 80): 20 px from the middle point, a gap of 15 px beyond its outline.
  std::vector<perch::pixel> points;
  for (int x = 10; x <= 50; ++x) points.push_back({x, 50});
  const std::vector<float> radius(points.size(), 5.5f);
  std::vector<float> gaps(points.size()), reach(points.size(), 0.0f);
  const std::vector<perch::owned_disc> discs{{30.0f, 80.0f, 10.0f, 1}, {30.0f, 50.0f, 5.0f, 0}};
  perch::workspace ws;
  auto index = perch::disc_index::build(discs, 100, 100, ws);
  REQUIRE(index);
  const perch::limb_neighbourhood limb{points, radius, perch::owner_set{{0, -1, -1}}, gaps, reach};
  const perch::limb_clearance around(*index, std::span<const perch::limb_neighbourhood>(&limb, 1));
  const perch::image<std::uint8_t> empty(100, 100, 0);
  const perch::tree_pixel_counter tree(empty.view());
  perch::window_measures m = window(0, 50);
  m.limb = 0;
  m.first = 0;
  m.last = 40;
  m.mm_per_px = 2.0f;  // 15 px: 30 mm
  const perch::window_context context(tree, m, {10, 50}, {50, 50}, 5.5f, {0, -1}, &around);
  CHECK(context.limb_gap_mm(100.0f) == doctest::Approx(30.0f));
  CHECK(perch::clearance{.margin_mm = 70.0f, .uncertainty_px = 0.0f}(m, context) ==
        doctest::Approx(40.0f));
  // The gap must clear the margin by the uncertainty (a pixel at the window's scale).
  CHECK(perch::clearance{.margin_mm = 70.0f, .uncertainty_px = 1.0f}(m, context) ==
        doctest::Approx(42.0f));
  CHECK(perch::clearance{.margin_mm = 29.0f, .uncertainty_px = 1.0f}(m, context) ==
        doctest::Approx(1.0f));
  CHECK(perch::clearance{.margin_mm = 28.0f, .uncertainty_px = 1.0f}(m, context) == 0.0f);
  CHECK(perch::clearance{.margin_mm = 20.0f, .uncertainty_px = 0.0f}(m, context) == 0.0f);
  // Only the window's points: x = 10 … 20 is √(10² + 30²) − 10 − 5 = 16.6 px from it.
  perch::window_measures left = m;
  left.last = 10;
  const perch::window_context side(tree, left, {10, 50}, {20, 50}, 5.5f, {0, -1}, &around);
  CHECK(side.limb_gap_mm(100.0f) == doctest::Approx(2.0f * (std::sqrt(1000.0f) - 15.0f)));
  CHECK(perch::clearance{.margin_mm = 70.0f, .uncertainty_px = 0.0f}(left, side) ==
        doctest::Approx(70.0f - 2.0f * (std::sqrt(1000.0f) - 15.0f)));
  // No surroundings given: clear.
  const perch::window_context bare(tree, m, {10, 50}, {50, 50}, 5.5f, {0, -1});
  CHECK(perch::clearance{}(m, bare) == 0.0f);
  // Validation; the share-of-band rule is `clutter` now.
  CHECK(perch::clearance{}.validate());
  CHECK(perch::clearance{}.name == "clearance");
  CHECK(perch::clearance{}.unit == "mm");
  CHECK(perch::clearance{.margin_mm = std::nanf("")}.validate().error().code ==
        errc::invalid_parameter);
  CHECK(perch::clearance{.uncertainty_px = -1.0f}.validate().error().code ==
        errc::invalid_parameter);
  CHECK(perch::clutter{}.name == "clutter");
  CHECK(perch::clutter{}.unit == "share");
  CHECK(!perch::clutter{.margin_mm = -1.0f}.validate());
  CHECK(perch::clutter{.margin_mm = 20.0f, .max_share = 0.0f}(m, bare) == 0.0f);  // nothing there
}

TEST_CASE("constraints: one_limb allows a limb's taper and an outline pixel, not a swelling") {
  const perch::one_limb one{};
  CHECK(one.name == "one_limb");
  CHECK(one.unit == "px");
  perch::window_measures m = window(0, 40.0f);
  m.radius_low_px = 10.0f;  // allowed: 1 px + 10 % of 10 px = 2 px above the lower tercile
  m.radius_max_px = 12.0f;
  CHECK(one(m) == 0.0f);
  m.radius_max_px = 15.5f;  // another limb lying along it: 3.5 px past what one limb allows
  CHECK(one(m) == doctest::Approx(3.5f));
  m.radius_low_px = 40.0f;  // a thick limb tapers by more pixels: 1 + 4 px
  m.radius_max_px = 45.0f;
  CHECK(one(m) == 0.0f);
  m.radius_max_px = 46.0f;
  CHECK(one(m) == doctest::Approx(1.0f));
  // Not measured: passes.
  m.radius_low_px = 0.0f;
  CHECK(one(m) == 0.0f);
  m.radius_low_px = std::nanf("");
  CHECK(one(m) == 0.0f);
  // Own values; validation.
  m.radius_low_px = 10.0f;
  m.radius_max_px = 12.0f;
  CHECK(perch::one_limb{.taper = 0.0f, .uncertainty_px = 0.5f}(m) == doctest::Approx(1.5f));
  CHECK(one.validate());
  CHECK(perch::one_limb{.taper = -0.1f}.validate().error().code == errc::invalid_parameter);
  CHECK(perch::one_limb{.uncertainty_px = std::nanf("")}.validate().error().code ==
        errc::invalid_parameter);
}
