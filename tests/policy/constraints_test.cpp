#include "perch/policy/constraints.hpp"

#include <doctest/doctest.h>

#include <cmath>

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
