// SPDX-License-Identifier: BSL-1.0
// The tracker's fuzz driver, shared by the libFuzzer target (tests/fuzz/fuzz_tracker.cpp) and
// the sanitizer-built unit test (tracker_fuzz_test.cpp): input bytes choose the tracker's
// options (some invalid), then frame after frame an operation: a result with garbage sites and
// near misses (huge, NaN and infinite measures, any rule name and miss), a motion (NaN, inf,
// huge, folding, projective), another frame size, no tree, a missing frame, a failed analysis,
// a reset; half the inputs with a camera, so tracks carry depths (the motion's and the frame's
// scale uncertainty fuzzed too). After every call the result must hold the tracker's
// invariants; a violation calls `report` (the fuzzer traps, the test reports).
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <string_view>
#include <vector>

#include "perch/track.hpp"

namespace perch::test {

/// Reads the fuzzer's bytes in order; zeros once they run out.
class byte_reader {
 public:
  byte_reader(const std::uint8_t* data, std::size_t size) noexcept : data_(data), size_(size) {}
  [[nodiscard]] bool done() const noexcept { return at_ >= size_; }
  std::uint8_t byte() noexcept { return at_ < size_ ? data_[at_++] : std::uint8_t{0}; }

  /// A float that is often hostile: NaN, ±∞, 0, negative, huge, tiny, or a plain value in
  /// [0, `plain`).
  float hostile(float plain) noexcept {
    const std::uint8_t b = byte();
    switch (b % 10) {
      case 0: return std::numeric_limits<float>::quiet_NaN();
      case 1: return std::numeric_limits<float>::infinity();
      case 2: return -std::numeric_limits<float>::infinity();
      case 3: return 0.0f;
      case 4: return -plain * static_cast<float>(byte()) / 255.0f;
      case 5: return 3.0e38f;
      case 6: return 1.0e-30f;
      default: return plain * static_cast<float>(byte()) / 255.0f;
    }
  }

  /// Mostly a plain value in [0, `plain`), now and then a hostile one.
  float mostly(float plain) noexcept {
    return byte() < 224 ? plain * static_cast<float>(byte()) / 255.0f : hostile(plain);
  }

  std::int32_t coordinate(int extent) noexcept {
    const std::uint8_t b = byte();
    if (b == 255) return std::numeric_limits<std::int32_t>::max();
    if (b == 254) return std::numeric_limits<std::int32_t>::min();
    return static_cast<std::int32_t>(static_cast<float>(extent) * static_cast<float>(b) / 200.0f) - 10;
  }

 private:
  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t at_ = 0;
};

/// The tracker's invariants after one call.
template <class Fail>
void check_result(const perch_tracker& tracker, const tracking_result& r, Fail&& fail) {
  const tracker_options& o = tracker.options();
  if (r.status == tracking_status::invalid_options) {
    if (static_cast<bool>(o.validate()) || !r.tracks.empty() || r.target != nullptr) fail("invalid options");
    return;
  }
  if (r.tracks.size() > perch_tracker::max_tracks) fail("too many tracks");
  int doubtful = 0;
  for (std::size_t i = 0; i < r.tracks.size(); ++i) {
    const perch_track& t = r.tracks[i];
    if (t.id == 0) fail("track id 0");
    for (std::size_t j = 0; j < i; ++j)
      if (r.tracks[j].id == t.id) fail("duplicate id");
    if (!t.position_px.allFinite() || !t.axis.allFinite()) fail("a track's position or axis is not finite");
    if (!std::isfinite(t.window_px)) fail("a track's window length is not finite");
    if (!std::isfinite(t.penalty) || !std::isfinite(t.heading_deg) || !std::isfinite(t.slope_deg) ||
        !std::isfinite(t.diameter_mm))
      fail("a track's smoothed measure is not finite");
    if (t.has_position && !t.position_m.allFinite()) fail("a track's metric position is not finite");
    if (t.has_position && !(t.depth_uncertainty >= 0 && t.depth_uncertainty <= 1))
      fail("a track's depth uncertainty is not in [0, 1]");
    if (t.doubtful) ++doubtful;
  }
  if (doubtful > 1) fail("more than one doubtful track");
  if (r.target != nullptr) {
    if (r.target < r.tracks.data() || r.target >= r.tracks.data() + r.tracks.size())
      fail("target outside the tracks");
    const perch_track& t = *r.target;
    if (t.state != track_state::confirmed) fail("target not confirmed");
    // Doubtful when this frame did not confirm it: its last match failed a rule, or it is unseen.
    if (t.doubtful != (!t.feasible || t.misses > 0))
      fail("doubtful flag disagrees with the last match and this frame's sighting");
    // Never beyond the limits: within the rule's noise for fewer than doubtful_frames, beyond
    // it for fewer than infeasible_frames.
    if (!t.feasible && t.infeasible_streak >= (t.marginal ? o.doubtful_frames : o.infeasible_frames))
      fail("doubtful target kept too long");
  } else if (doubtful != 0) {
    fail("a doubtful track that is not the target");
  }
  if (r.changed && r.change.to != (r.target ? r.target->id : 0u)) fail("change.to is not the target");
  if (r.changed && r.change.from == r.change.to) fail("a change to the same target");
}

/// A few spots that frames come back to, so that tracks are confirmed, become targets and meet
/// near misses at their spots (garbage alone seldom gets that far).
struct fuzz_scene {
  pixel spots[4];
  explicit fuzz_scene(byte_reader& in) {
    for (pixel& p : spots)
      p = {static_cast<std::int32_t>(in.byte()) * 2 + 40, static_cast<std::int32_t>(in.byte()) + 100};
  }
};

/// One frame's result from the bytes: up to 6 sites and 4 near misses, mostly at the scene's
/// spots (jittered, with small misses), else anywhere with hostile measures.
struct fuzz_frame {
  std::vector<perch_site> sites;
  std::vector<near_miss> misses;
  perch_result result;

  fuzz_frame(byte_reader& in, const fuzz_scene& scene, int width, int height) {
    // Rules with their units, and two mismatched: a unit the noise table cannot convert.
    static constexpr std::string_view rules[][2] = {
        {"clearance", "mm"}, {"resolution", "px"}, {"diameter", "mm"}, {"max_slope", "deg"},
        {"bend", "deg"},     {"border", "px"},     {"supported", ""},  {"custom", "mm"},
        {"clearance", "share"}, {"max_slope", "mm"}};
    const int site_count = in.byte() % 7, miss_count = in.byte() % 5;
    for (int i = 0; i < site_count; ++i) {
      perch_site s;
      fill(in, scene, s.window, width, height);
      s.penalty = in.mostly(1.0f);
      sites.push_back(s);
    }
    for (int i = 0; i < miss_count; ++i) {
      near_miss m;
      const std::uint8_t rule = in.byte() % 10;
      m.constraint = rules[rule][0];
      m.unit = rules[rule][1];
      m.miss = in.byte() % 2 == 0 ? in.mostly(3.0f) : in.mostly(20.0f);
      m.present = in.byte() % 8 != 0;
      fill(in, scene, m.window, width, height);
      misses.push_back(m);
    }
    result.width = width;
    result.height = height;
    result.mm_per_px = in.mostly(10.0f);
    result.scale_uncertainty = in.mostly(0.1f);
    result.sites = sites;
    result.near_misses = misses;
    const std::uint8_t outcome = in.byte() % 16;
    result.outcome = outcome == 0 ? perch_outcome::no_tree
                     : sites.empty() || outcome == 1 ? perch_outcome::no_perch
                                                     : perch_outcome::found;
  }

  static void fill(byte_reader& in, const fuzz_scene& scene, window_measures& w, int width,
                   int height) {
    const std::uint8_t at = in.byte();
    if (at % 4 != 0) {  // at a spot, a pixel or two off, a level window 60 px long
      const pixel p = scene.spots[at / 4 % 4];
      w.centre = {p.x + at % 3 - 1, p.y + at / 16 % 3 - 1};
      w.base_end = {w.centre.x - 30, w.centre.y};
      w.tip_end = {w.centre.x + 30, w.centre.y};
    } else {
      w.centre = {in.coordinate(width), in.coordinate(height)};
      w.base_end = {in.coordinate(width), in.coordinate(height)};
      w.tip_end = in.byte() % 4 == 0 ? w.base_end : pixel{in.coordinate(width), in.coordinate(height)};
    }
    w.heading_deg = in.mostly(360.0f) - 180.0f;
    w.slope_deg = in.mostly(90.0f);
    w.claw_diameter_mm = in.mostly(150.0f);
    w.mm_per_px = in.mostly(10.0f);
    w.has_position = in.byte() % 2 == 0;
    // Camera-frame points mostly within 10 m, now and then hostile (NaN, behind the camera,
    // huge, tiny): a tracker with a camera carries and measures their depth.
    w.position_m = point3f(in.mostly(5.0f), in.mostly(5.0f), in.mostly(10.0f));
  }
};

/// A motion from the bytes: identity, a plausible similarity, or a hostile homography; its
/// scale's uncertainty none, plausible or hostile.
inline camera_motion fuzz_motion(byte_reader& in) {
  const std::uint8_t kind = in.byte() % 8;
  if (kind < 3) return camera_motion::identity();
  camera_motion m;
  switch (kind % 2) {
    case 0:
      m = camera_motion::similarity_about({in.mostly(640.0f), in.mostly(480.0f)},
                                          0.9f + in.mostly(0.2f), in.mostly(20.0f) - 10.0f,
                                          {in.mostly(40.0f) - 20.0f, in.mostly(40.0f) - 20.0f});
      break;
    default:
      for (float& v : m.h) v = in.hostile(2.0f);
      break;
  }
  if (kind >= 6) m.scale_uncertainty = in.mostly(0.05f);
  return m;
}

/// Tracker options from the bytes: the defaults, tightened or loosened, now and then invalid.
inline tracker_options fuzz_options(byte_reader& in) {
  tracker_options o;
  const std::uint8_t b = in.byte();
  if (b % 2 == 0) return o;
  if (b % 16 == 1) {  // anything, valid or not
    o.confirm_frames = in.byte() % 6;
    o.doubtful_frames = in.byte() % 16;
    o.switch_margin = in.hostile(0.2f);
    o.along_gain = in.hostile(1.0f);
    o.across_gate_windows = in.hostile(1.0f);
    o.depth_drift = in.hostile(0.01f);
    return o;
  }
  o.confirm_frames = 1 + in.byte() % 5;
  o.drop_frames = 1 + in.byte() % 8;
  o.forget_frames = in.byte() % 20;
  o.infeasible_frames = 1 + in.byte() % 5;
  o.doubtful_frames = 1 + in.byte() % 16;
  o.switch_frames = 1 + in.byte() % 10;
  o.switch_margin = in.mostly(0.2f);
  o.depth_drift = in.mostly(0.01f);
  return o;
}

/// Runs the bytes through a tracker, checking every result with `fail`.
template <class Fail>
void run_tracker_fuzz(const std::uint8_t* data, std::size_t size, Fail&& report) {
  byte_reader in(data, size);
  static perch_tracker tracker;  // static: big, and the fuzzer runs many inputs
  const tracker_options options = fuzz_options(in);
  // Half the inputs with a camera, so the metric path (depth carried and measured) runs too.
  tracker = in.byte() % 2 == 0 ? perch_tracker(options)
                               : perch_tracker(options, pinhole{500, 500, 320, 240});
  const fuzz_scene scene(in);
  int width = 640, height = 480;
  for (int step = 0; step < 200 && !in.done(); ++step) {
    const std::uint8_t op = in.byte() % 32;
    tracking_result r;
    if (op == 0) {
      r = tracker.skip(fuzz_motion(in));
    } else if (op == 1) {
      r = tracker.update(result<perch_result>(fail(errc::empty_image, "fuzz: a failed analysis")),
                         fuzz_motion(in));
    } else if (op == 2) {
      tracker.reset();
      continue;
    } else {
      if (op == 3 && in.byte() % 4 == 0) {  // another frame size, now and then nonsense
        width = static_cast<int>(in.byte()) * 8 - 16;
        height = static_cast<int>(in.byte()) * 8 - 16;
      }
      const fuzz_frame frame(in, scene, width, height);
      r = tracker.update(frame.result, op < 20 ? camera_motion::identity() : fuzz_motion(in));
    }
    check_result(tracker, r, report);
#ifdef PERCH_FUZZ_COVERAGE
    PERCH_FUZZ_COVERAGE(r);
#endif
  }
}

}  // namespace perch::test
