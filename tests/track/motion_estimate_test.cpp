// SPDX-License-Identifier: BSL-1.0
// motion_estimator: the camera's motion between two frames of an approach sequence, from the
// masks' skeleton junctions and ends, matches the true motion; the first frame and a frame with
// no tree give the identity, not estimated; no allocation after warm-up; deterministic.
#include "perch/track.hpp"

#include <doctest/doctest.h>

#include <cmath>

#include "allocation_counter.hpp"
#include "perch/pli.hpp"
#include "support/find_perch_instances.hpp"
#include "support/sequence.hpp"

namespace st = perch::support;

namespace {

/// The largest distance between where `a` and `b` take points of the frame's middle half.
float disagreement(const perch::camera_motion& a, const perch::camera_motion& b, int width,
                   int height) {
  float worst = 0;
  for (float u = 0.25f; u <= 0.75f; u += 0.25f)
    for (float v = 0.25f; v <= 0.75f; v += 0.25f) {
      const perch::point2f p(u * static_cast<float>(width), v * static_cast<float>(height));
      worst = std::max(worst, (a.apply(p) - b.apply(p)).norm());
    }
  return worst;
}

/// `find_perch` on a sequence's frame at its true scale.
perch::result<perch::perch_result> analyse(const st::sequence_frame& frame, perch::workspace& ws) {
  return perch::find_perch(frame.mask.view(), perch::tendon_claw{},
                           perch::fixed_scale{frame.tree.mm_per_px}, ws);
}

}  // namespace

TEST_CASE("the estimated motion between approach frames matches the true one") {
  st::sequence_options o;
  o.frames = 30;
  o.jitter_px = 4.0f;  // shake enough that the identity is clearly wrong
  const st::approach_sequence seq = st::evaluation_sequence(0, o);
  perch::workspace ws;
  perch::motion_estimator estimator;
  int estimated = 0;
  for (int f = 10; f < 16; ++f) {
    const st::sequence_frame frame = seq.frame(f);
    const auto found = analyse(frame, ws);
    REQUIRE(found);
    perch::test::allocation_scope scope;
    const perch::motion_estimate m = estimator.update(*found);
    CHECK(scope.count() == 0);
    if (f == 10) {
      CHECK(!m.estimated);
      continue;
    }
    CHECK(m.keypoints >= 6);
    if (!m.estimated) continue;
    ++estimated;
    const float error = disagreement(m.motion, frame.motion, frame.mask.width(), frame.mask.height());
    const float identity_error =
        disagreement(perch::camera_motion::identity(), frame.motion, frame.mask.width(), frame.mask.height());
    INFO("frame " << f << " inliers " << m.inliers << " of " << m.keypoints << " identity error " << identity_error);
    // Over the middle half of the frame, beyond the small far-away tree the keypoints cover.
    CHECK(error < 4.0f);
    CHECK(error < 0.25f * identity_error);
  }
  CHECK(estimated >= 4);
}

TEST_CASE("the estimated zoom of an approach is not biased toward 1, and states its uncertainty") {
  // Sequence 3's first second: limbs cut by the frame's edge end there, and those ends stay on
  // the edge as the picture grows. Taken as keypoints they pulled the zoom toward 1: 0.22 % a
  // frame too little on average here, which a depth carried by the motion accumulates.
  const st::approach_sequence seq = st::evaluation_sequence(3, st::sequence_options{});
  perch::workspace ws;
  perch::motion_estimator estimator;
  double error_sum = 0, error_squares = 0, stated_squares = 0;
  int estimated = 0;
  for (int f = 0; f < 30; ++f) {
    const st::sequence_frame frame = seq.frame(f);
    const auto found = analyse(frame, ws);
    REQUIRE(found);
    const perch::motion_estimate m = estimator.update(*found);
    CHECK(m.motion.valid());
    if (!m.estimated) {
      CHECK(m.motion.scale_uncertainty == doctest::Approx(0.25f));  // any zoom the search allows
      continue;
    }
    const perch::point2f centre(0.5f * static_cast<float>(seq.width()),
                                0.5f * static_cast<float>(seq.height()));
    const float ratio = m.motion.scale_at(centre) / frame.motion.scale_at(centre);
    const double error = std::log(static_cast<double>(ratio));
    error_sum += error;
    error_squares += error * error;
    const auto stated = static_cast<double>(m.motion.scale_uncertainty);
    stated_squares += stated * stated;
    ++estimated;
  }
  REQUIRE(estimated >= 25);
  const double mean = error_sum / estimated;
  const double rms = std::sqrt(error_squares / estimated);
  const double stated = std::sqrt(stated_squares / estimated);
  INFO("mean " << mean << " rms " << rms << " stated " << stated);
  CHECK(std::abs(mean) < 0.0008);
  // The stated uncertainty is of the error's size (from the inliers' residuals: a little less).
  CHECK(stated > 0.4 * rms);
  CHECK(stated < 2.5 * rms);
}

TEST_CASE("motion_estimator: no tree gives the identity; the same frames give the same motion") {
  perch::image<std::uint8_t> empty(64, 48, 0);
  perch::workspace ws;
  perch::motion_estimator estimator;
  const auto found = perch::find_perch(empty.view(), ws);
  REQUIRE(found);
  CHECK(!estimator.update(*found).estimated);
  CHECK(!estimator.update(*found).estimated);

  const st::approach_sequence seq = st::evaluation_sequence(2, st::sequence_options{});
  const st::sequence_frame a = seq.frame(50), b = seq.frame(51);
  perch::motion_estimator first, second;
  for (perch::motion_estimator* e : {&first, &second}) {
    for (const st::sequence_frame* f : {&a, &b}) {
      const auto r = perch::find_perch(f->mask.view(), perch::tendon_claw{},
                                       perch::fixed_scale{f->tree.mm_per_px}, ws);
      REQUIRE(r);
      (void)e->update(*r);
    }
  }
  // Both estimators saw the same frames: their last estimates agree bit for bit.
  const auto r = perch::find_perch(b.mask.view(), perch::tendon_claw{},
                                   perch::fixed_scale{b.tree.mm_per_px}, ws);
  REQUIRE(r);
  const perch::motion_estimate x = first.update(*r), y = second.update(*r);
  CHECK(x.motion.h == y.motion.h);
  CHECK(x.inliers == y.inliers);
  // The same frame twice: no motion.
  if (x.estimated) CHECK(disagreement(x.motion, perch::camera_motion::identity(), 640, 480) < 0.5f);
}
