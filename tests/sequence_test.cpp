// SPDX-License-Identifier: BSL-1.0
// support/sequence.hpp: approach sequences are deterministic, their motion is the camera's,
// the approach and roll stay in their ranges, and the truth follows the tree through the frames.
#include "support/sequence.hpp"

#include <doctest/doctest.h>

#include <cmath>
#include <cstring>

namespace st = perch::support;

TEST_CASE("an approach sequence: deterministic frames, true motion, scale 1/3 to 1, bounded roll") {
  st::sequence_options o;
  o.frames = 12;
  o.dropout_chance = 0.5f;
  const st::approach_sequence a = st::evaluation_sequence(0, o), b = st::evaluation_sequence(0, o);
  REQUIRE(a.frames() == 12);
  int dropouts = 0;
  for (int f = 0; f < a.frames(); ++f) {
    const st::sequence_frame x = a.frame(f), y = b.frame(f);
    REQUIRE(x.mask.width() == a.width());
    CHECK(std::memcmp(x.mask.data(), y.mask.data(),
                      static_cast<std::size_t>(x.mask.width() * x.mask.height())) == 0);
    CHECK(std::abs(x.roll_deg) <= o.max_roll_deg + o.jitter_deg);
    dropouts += x.dropouts;
    if (f == 0) CHECK(x.scale == doctest::Approx(1.0f / 3.0f));
    if (f == a.frames() - 1) CHECK(x.scale == doctest::Approx(1.0f));
    if (f == 0) continue;
    // The motion carries the previous frame's view of a world point to this frame's.
    const st::sequence_frame prev = a.frame(f - 1);
    const perch::point2f world(300, 200);
    const perch::point2f expected = x.from_world.apply(world);
    const perch::point2f moved = x.motion.apply(prev.from_world.apply(world));
    CHECK((moved - expected).norm() < 0.01f);
    // The tree's limbs are scaled with the camera.
    CHECK(x.tree.limbs[0].diameter_px[0] / prev.tree.limbs[0].diameter_px[0] ==
          doctest::Approx(x.scale / prev.scale));
  }
  CHECK(dropouts > 0);
}

TEST_CASE("the truth under roll: a rolled frame's truth matches the unrolled frame's") {
  st::sequence_options level, rolled;
  level.frames = rolled.frames = 2;
  level.max_roll_deg = 0;
  level.jitter_deg = 0;
  rolled.jitter_deg = 0;
  const st::sequence_frame a = st::evaluation_sequence(1, level).frame(1);
  const st::sequence_frame b = st::evaluation_sequence(1, rolled).frame(1);
  const st::perch_truth ta(a.tree, st::spec_for(a)), tb(b.tree, st::spec_for(b));
  // Same tree, same distance: a roll moves the stretches in the picture but keeps their
  // length where the frame's border does not cut them (the slope rule uses the horizon).
  REQUIRE(ta.has_perch());
  float la = 0, lb = 0;
  for (const auto& s : ta.stretches()) la += s.arc_end_px - s.arc_begin_px;
  for (const auto& s : tb.stretches()) lb += s.arc_end_px - s.arc_begin_px;
  CHECK(lb > 0.5f * la);
  // Without telling the truth about the roll, the slope rule judges against image rows.
  st::claw_spec unaware;
  const st::perch_truth tc(b.tree, unaware);
  float lc = 0;
  for (const auto& s : tc.stretches()) lc += s.arc_end_px - s.arc_begin_px;
  CHECK(std::abs(b.roll_deg) > 1.0f);
  CHECK(lc != lb);
}

TEST_CASE("a sequence's depth image: the tree at the distance its scale implies, no return elsewhere") {
  st::sequence_options o;
  o.frames = 5;
  const st::approach_sequence a = st::evaluation_sequence(2, o);
  const perch::pinhole camera = a.camera();
  CHECK(camera.validate().has_value());
  CHECK(camera.cx == doctest::Approx(0.5 * (a.width() - 1)));
  float first_z = 0, last_z = 0;
  for (const int f : {0, a.frames() - 1}) {
    const st::sequence_frame frame = a.frame(f);
    const perch::image<std::uint16_t> depth = a.depth_mm(frame);
    REQUIRE(depth.width() == a.width());
    REQUIRE(depth.height() == a.height());
    const float z = frame.tree.mm_per_px * camera.fx;  // a pinhole sees Z / f mm per pixel
    CHECK(a.distance_mm(frame) == doctest::Approx(z));
    // A pixel's true point: on the tree's plane, seen back at that pixel.
    const perch::point2f p(100.5f, 40.0f);
    const perch::point3f q = a.point_m(frame, p);
    CHECK(q.z() == doctest::Approx(1e-3f * z));
    CHECK((camera.project(q) - p).norm() < 1e-3f);
    std::size_t tree = 0, wrong = 0;
    for (int y = 0; y < depth.height(); ++y)
      for (int x = 0; x < depth.width(); ++x) {
        const bool on_tree = frame.tree.mask(x, y) != 0;
        if (on_tree) ++tree;
        if (std::abs(static_cast<float>(depth(x, y)) - (on_tree ? z : 0.0f)) > 0.5f) ++wrong;
      }
    CHECK(tree > 0);
    CHECK(wrong == 0);
    (f == 0 ? first_z : last_z) = z;
  }
  CHECK(first_z / last_z == doctest::Approx(o.start_distance).epsilon(1e-3));  // the 3x approach
}
