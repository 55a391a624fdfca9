// SPDX-License-Identifier: BSL-1.0
/// \file
/// `perch_tracker`: one stable perch target across the frames of an approach. Each frame's
/// `find_perch` result (its ranked sites and near misses) is matched to the tracks of the
/// frames before, moved with the camera's motion; tracks keep a persistent id, a smoothed
/// position and smoothed measures, and one confirmed track is the target, changed only for a
/// stated reason. Fixed capacities: no allocation ever, no exceptions, deterministic.
#pragma once

#include "perch/core/cxx20.hpp"  // first: a clear error before C++20 code

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <optional>
#include <span>
#include <string_view>

#include "perch/core/result.hpp"
#include "perch/pipeline.hpp"
#include "perch/track/motion.hpp"
#include "perch/track/rule_noise.hpp"

namespace perch {

/// How a frame went for the tracker.
enum class tracking_status : std::uint8_t {
  ok,               ///< the frame was analysed and its sites matched to the tracks
  no_perch,         ///< analysed, but no site passed every constraint (near misses matched)
  no_tree,          ///< the mask had no tree: every track coasts on the motion and ages
  wrong_size,       ///< the frame's size is not the first frame's: tracks coast and age
  bad_motion,       ///< the motion is not finite or not a camera's: tracks stay and age
  missing_frame,    ///< no analysis for this frame (`skip`, or `find_perch` failed): tracks age
  invalid_options,  ///< the tracker's options are invalid (`tracker_options::validate`)
};

[[nodiscard]] constexpr std::string_view to_string(tracking_status s) noexcept {
  switch (s) {
    case tracking_status::ok: return "ok";
    case tracking_status::no_perch: return "no_perch";
    case tracking_status::no_tree: return "no_tree";
    case tracking_status::wrong_size: return "wrong_size";
    case tracking_status::bad_motion: return "bad_motion";
    case tracking_status::missing_frame: return "missing_frame";
    case tracking_status::invalid_options: return "invalid_options";
  }
  return "unknown";
}

/// A track's life: `tentative` until seen in `confirm_frames` frames in a row, then
/// `confirmed`; `lost` after `drop_frames` frames unseen (it may be found again, then it is
/// confirmed again; it is forgotten after `forget_frames` more).
enum class track_state : std::uint8_t { tentative, confirmed, lost };

[[nodiscard]] constexpr std::string_view to_string(track_state s) noexcept {
  switch (s) {
    case track_state::tentative: return "tentative";
    case track_state::confirmed: return "confirmed";
    case track_state::lost: return "lost";
  }
  return "unknown";
}

/// Why the target changed.
enum class target_change_reason : std::uint8_t {
  acquired,    ///< there was no target; this confirmed track is the best
  lost,        ///< the target was not seen for `drop_frames` frames
  infeasible,  ///< the target's site failed a constraint by more than its measurement noise
               ///< (`measurement_noise`), `infeasible_frames` near-miss frames in a row
  better,      ///< another track was better by `switch_margin` for `switch_frames` frames
  doubtful,    ///< the target's site failed a constraint within its noise `doubtful_frames`
               ///< frames in a row: too long to be the mask's flicker
};

[[nodiscard]] constexpr std::string_view to_string(target_change_reason r) noexcept {
  switch (r) {
    case target_change_reason::acquired: return "acquired";
    case target_change_reason::lost: return "lost";
    case target_change_reason::infeasible: return "infeasible";
    case target_change_reason::better: return "better";
    case target_change_reason::doubtful: return "doubtful";
  }
  return "unknown";
}

/// The tracker's knobs: association gates and hysteresis. Each trades stability against
/// reaction time; the defaults suit 30 fps.
struct tracker_options {
  /// Frames in a row a new track must be seen before it is confirmed (and may become the
  /// target). More: flickering false sites never become targets, but the first lock is later.
  std::uint32_t confirm_frames = 3;
  /// Frames unseen before a track is lost (and a lost target replaced). More: a limb that drops
  /// out of the mask for a few frames keeps its track, but a target that really left is
  /// replaced later.
  std::uint32_t drop_frames = 5;
  /// Frames a lost track is kept after that, to be found again under its id.
  std::uint32_t forget_frames = 15;
  /// Smoothed penalty by which another confirmed track must beat the target to take over
  /// (penalties of `pli_penalty` lie in [0, 1]). More: fewer switches between near-equal
  /// sites, but a clearly better site waits longer.
  float switch_margin = 0.08f;
  /// Frames in a row the margin must hold before the switch. More: a frame's noise never
  /// switches, but a better site takes over later.
  std::uint32_t switch_frames = 8;
  /// Frames in a row the target's site must fail a constraint (matched to a near miss) before
  /// it is replaced, when the last miss is larger than the rule's measurement noise
  /// (`measurement_noise`). More: a one-frame mismeasure keeps the target; fewer: a truly
  /// infeasible target is left sooner.
  std::uint32_t infeasible_frames = 3;
  /// Frames in a row the target may stay (flagged `doubtful`) while its site fails a constraint
  /// by no more than the rule's measurement noise: a margin that flickers with the mask's
  /// noise, not a limb that changed. Never more: a miss that lasts is real. More: fewer
  /// switches away from a target the truth still calls feasible; fewer: a target that truly
  /// turned marginal is left sooner.
  std::uint32_t doubtful_frames = 5;
  /// Weight of a new measurement across the limb (0, 1]: the rest is the motion's prediction.
  /// Less: steadier position, but slower to correct a wrong motion.
  float across_gain = 0.5f;
  /// Weight of a new measurement along the limb (0, 1]. The best window slides along a limb by
  /// a stride or two from frame to frame (outline noise), which is not the limb moving: a low
  /// gain holds the point still, a high one follows a feasible stretch that shrinks faster.
  float along_gain = 0.15f;
  /// Weight of a new measurement of the slope, heading, diameter and penalty (0, 1].
  float measure_gain = 0.3f;
  /// How far a track's depth may move in a frame beyond what the motion's scale says, relative
  /// (1σ; 0.002 = 0.2 %): a limb that does not face the camera, a motion whose scale is off by
  /// more than its `scale_uncertainty` states (visual odometry that states none, the identity
  /// when the motion is unknown). It is added to the motion's own uncertainty each frame and
  /// sets how much a depth measurement outweighs the motion's prediction (see
  /// `perch_tracker`). Less: a steadier depth with a noisy depth camera, as long as the motion
  /// is as good as it says; more: a wrong motion's depth is corrected sooner.
  float depth_drift = 0.002f;
  /// Gate along the limb: a site is matched to a track only within this many window lengths of
  /// its predicted position along the limb. More: survives a worse motion, but may take
  /// another site of the same limb.
  float along_gate_windows = 1.0f;
  /// Gate across the limb, in window lengths. Less: parallel limbs close together are never
  /// confused, but a poor motion estimate loses tracks.
  float across_gate_windows = 0.35f;
  /// Gate on the limb's axis, degrees (folded, so a limb walked either way matches): crossing
  /// limbs at a larger angle are never confused; less than the camera's roll between frames
  /// loses tracks.
  float axis_gate_deg = 30.0f;

  [[nodiscard]] status validate() const noexcept {
    if (confirm_frames == 0 || drop_frames == 0 || switch_frames == 0 || infeasible_frames == 0 ||
        doubtful_frames == 0)
      return fail(errc::invalid_parameter, "tracker_options: frame counts must be >= 1");
    for (const float g : {across_gain, along_gain, measure_gain})
      if (!(g > 0 && g <= 1)) return fail(errc::invalid_parameter, "tracker_options gains");
    if (!(depth_drift >= 0 && depth_drift <= 1))
      return fail(errc::invalid_parameter, "tracker_options.depth_drift");
    if (!(switch_margin >= 0 && std::isfinite(switch_margin)))
      return fail(errc::invalid_parameter, "tracker_options.switch_margin");
    for (const float g : {along_gate_windows, across_gate_windows})
      if (!(g > 0 && std::isfinite(g))) return fail(errc::invalid_parameter, "tracker_options gates");
    if (!(axis_gate_deg > 0 && axis_gate_deg <= 90))
      return fail(errc::invalid_parameter, "tracker_options.axis_gate_deg");
    return {};
  }
};

/// One perch site followed across frames. Positions are in the current frame's input pixels.
struct perch_track {
  std::uint32_t id = 0;        ///< persistent, from 1 (0 means none)
  track_state state = track_state::tentative;
  std::uint32_t age = 0;       ///< frames since it was born (0 in its first frame)
  std::uint32_t hits = 0;      ///< frames it was matched to a site or a near miss
  std::uint32_t misses = 0;    ///< frames in a row it was not matched
  std::uint32_t streak = 0;    ///< frames in a row it was matched
  point2f position_px = point2f::Zero();  ///< smoothed perch pixel
  point2f axis = point2f(1, 0);  ///< unit, along the limb from the trunk side to the tip
  float window_px = 0;         ///< the window's length in this frame, px (for the gates)
  float heading_deg = 0;       ///< smoothed `window_measures::heading_deg`
  float slope_deg = 0;         ///< smoothed slope
  float diameter_mm = 0;       ///< smoothed claw diameter
  float penalty = 0;           ///< smoothed penalty (of feasible matches)
  bool feasible = true;        ///< its last match was a ranked site (not a near miss)
  std::uint32_t infeasible_streak = 0;    ///< frames in a row matched to a near miss
  std::string_view failed_constraint{};   ///< the near miss's constraint, when not feasible
  std::string_view failed_unit{};         ///< its unit
  float failed_by = 0;                    ///< by how much it missed, in `failed_unit`
  bool marginal = false;  ///< not feasible, but by no more than the rule's measurement noise
  /// The target, kept though this frame did not confirm it: its last match failed a rule
  /// (within the rule's noise for fewer than `doubtful_frames` frames, or beyond it for fewer
  /// than `infeasible_frames`), or it was not seen in this frame (`misses` > 0: its position
  /// is the motion's prediction, for fewer than `drop_frames` frames). Only the target is ever
  /// doubtful; a planner should not commit to the grasp while it is.
  bool doubtful = false;
  std::uint32_t better_streak = 0;  ///< frames in a row it beat the target by the margin
  /// Camera-frame position, metres (x right, y down, z along the optical axis): `position_px`
  /// back-projected at the track's depth, which follows the camera's motion (see
  /// `perch_tracker`). Needs the tracker's camera and a frame whose site had depth.
  point3f position_m = point3f::Zero();
  bool has_position = false;
  /// The relative standard uncertainty (1σ) of `position_m`'s depth: what the measurements
  /// left and the motions since added (0.001 = 0.1 %; at most 1).
  float depth_uncertainty = 0;
  /// This frame's measurement of the matched site, unsmoothed (at the site's own pixel), when
  /// `measured`: matched in this frame to a site with depth.
  point3f measured_m = point3f::Zero();
  bool measured = false;
  bool matched = false;        ///< matched in this frame
};

/// A change of target: ids (0 = none) and why.
struct target_change {
  std::uint32_t from = 0;
  std::uint32_t to = 0;
  target_change_reason reason = target_change_reason::acquired;
  std::string_view constraint{};  ///< for `infeasible`, `doubtful`: the rule the old target failed
  std::string_view unit{};        ///< its unit
  float miss = 0;                 ///< by how much, in the last frame
  std::uint32_t frames = 0;       ///< near-miss frames in a row before it was left
};

/// What `perch_tracker::update` says about a frame. Spans point into the tracker: valid until
/// its next update.
struct tracking_result {
  tracking_status status = tracking_status::ok;
  std::uint32_t frame = 0;                 ///< frames seen before this one
  std::span<const perch_track> tracks{};   ///< live tracks, by id
  const perch_track* target = nullptr;     ///< the target, or null
  bool changed = false;                    ///< the target changed in this frame
  target_change change{};                  ///< how, when `changed`
  std::uint32_t candidates = 0;            ///< sites and near misses offered
  std::uint32_t unplaced = 0;              ///< candidates dropped for lack of track capacity
};

/// Follows the perch across frames. Fixed capacity (`max_tracks`, `max_candidates`): place it
/// once (statically on firmware), it never allocates. See `tracker_options` for the knobs.
///
/// Per frame, `update`: (1) moves every track with the camera's motion; (2) offers the frame's
/// ranked sites (feasible) and near misses (infeasible, named) as candidates; (3) gates each
/// track-candidate pair on the distance along and across the track's limb, in window lengths,
/// and on the angle between their axes; (4) matches greedily, cheapest pair first (ties by
/// track then candidate order: deterministic); (5) smooths matched tracks, ages the others,
/// opens tentative tracks on unmatched sites; (6) keeps or changes the target.
///
/// With depth (`depth_scale`) and the camera (the constructor's `camera`, the intrinsics of
/// the input pixels), a track's metric position is its pixel back-projected at its depth z, so
/// it moves with the camera as the pixel does. Step (1) predicts z with the motion's local
/// scale s at the track: z/s. A limb facing the camera that looks s times larger is s times
/// nearer: the homography a plane induces, H = K(R − t·nᵀ/d)K⁻¹ (Hartley & Zisserman,
/// Multiple View Geometry, 2nd ed., §13.1), scales the picture by d/(d − t_z) = z_prev/z_now
/// for a plane facing the camera; for a limb that leans, each measurement corrects the rest.
/// z and the measured depth are weighed by their uncertainties, as a scalar Kalman filter
/// (Kalman, "A new approach to linear filtering and prediction problems", J. Basic Eng. 82(1),
/// 1960) on the relative error of z: step (1) adds the motion's `scale_uncertainty` and
/// `depth_drift` (in quadrature) to z's relative variance P; step (5) takes a measured depth
/// with relative variance R (the frame's `scale_uncertainty`, the depth policy's stated
/// uncertainty, and the rounding of a depth image in whole millimetres, 1/√12 mm) with the
/// gain K = P/(P + R) and leaves (1 − K)·P. A fixed gain g instead trailed the approach by
/// (1 − g)/g frames of the motion's scale error (a motion estimated from the masks, good to
/// 0.3 % a frame, put z 16 mm too far on average at 4–15 m); a depth camera far noisier than
/// the motion is smoothed by the motion, a clean one is followed. Smoothing the metric point
/// itself would trail an approach and stand still while a track coasts; a constant-velocity
/// filter on z lags while it learns the rate and overshoots when the drone brakes to perch;
/// the motion gives this frame's change itself. Without a motion (the identity), only
/// `depth_drift` lets the measurements move z: it trails an approach unless the depth is clean.
class perch_tracker {
 public:
  static constexpr std::size_t max_tracks = 24;
  static constexpr std::size_t max_candidates = 32;

  /// `camera`: the intrinsics of the frames' input pixels, for metric positions (none: tracks
  /// carry only `measured_m`); one that is not valid makes the options invalid.
  explicit perch_tracker(const tracker_options& options = {},
                         const std::optional<pinhole>& camera = std::nullopt) noexcept
      : options_(options),
        camera_(camera),
        options_ok_(static_cast<bool>(options.validate()) &&
                    (!camera || static_cast<bool>(camera->validate()))) {}

  [[nodiscard]] const tracker_options& options() const noexcept { return options_; }

  /// Forgets every track and the frame size (e.g. when the camera's resolution changes).
  void reset() noexcept {
    count_ = 0;
    target_id_ = 0;
    width_ = height_ = 0;
    frame_ = 0;
  }

  /// One analysed frame. `motion` maps the previous frame's pixels to this one's (identity
  /// when not known). A result of another size than the first frame's, a `motion` that is not
  /// `valid()` or a mask with no tree: the tracks coast and age, and the status says why.
  [[nodiscard]] tracking_result update(const perch_result& frame,
                                       const camera_motion& motion = {}) noexcept {
    if (!options_ok_) return finish(tracking_status::invalid_options, {});
    if (!motion.valid()) return coast(tracking_status::bad_motion, camera_motion::identity());
    if (width_ == 0) {
      width_ = frame.width;
      height_ = frame.height;
    }
    if (frame.width != width_ || frame.height != height_)
      return coast(tracking_status::wrong_size, motion);
    if (frame.outcome == perch_outcome::no_tree) return coast(tracking_status::no_tree, motion);
    predict(motion);
    gather_candidates(frame);
    associate();
    const std::uint32_t unplaced = apply_matches();
    age_unmatched();
    tracking_result out =
        finish(frame.outcome == perch_outcome::found ? tracking_status::ok : tracking_status::no_perch,
               unplaced);
    return out;
  }

  /// `update` with `find_perch`'s result: an error counts as a missing frame.
  [[nodiscard]] tracking_result update(const result<perch_result>& frame,
                                       const camera_motion& motion = {}) noexcept {
    if (!frame) return skip(motion);
    return update(*frame, motion);
  }

  /// A frame without analysis (dropped, or its analysis failed): the tracks move with
  /// `motion` (when valid) and age.
  [[nodiscard]] tracking_result skip(const camera_motion& motion = {}) noexcept {
    if (!options_ok_) return finish(tracking_status::invalid_options, {});
    return coast(tracking_status::missing_frame,
                 motion.valid() ? motion : camera_motion::identity());
  }

  /// The live tracks, by id.
  [[nodiscard]] std::span<const perch_track> tracks() const noexcept {
    return std::span<const perch_track>(tracks_.data(), count_);
  }

 private:
  struct candidate {
    point2f position;
    point2f axis;  // unit, base → tip
    float window_px;
    float heading_deg, slope_deg, diameter_mm, penalty;
    point3f position_m;
    bool has_position;
    bool feasible;
    std::string_view constraint, unit;
    float miss;   // by how much a near miss failed, in `unit`
    float noise;  // the rule's measurement noise there, in `unit`
    std::int32_t track;  // matched track index, -1 none
  };
  /// How far along the limb, in windows, a near miss speaks for a track's spot.
  static constexpr float near_miss_reach_windows = 0.35f;

  struct pair_cost {
    float cost;
    std::uint16_t track, cand;
  };

  [[nodiscard]] static float wrap180(float deg) noexcept {
    while (deg > 180.0f) deg -= 360.0f;
    while (deg <= -180.0f) deg += 360.0f;
    return deg;
  }

  /// Angle between two axes regardless of direction, degrees in [0, 90].
  [[nodiscard]] static float axis_angle_deg(point2f a, point2f b) noexcept {
    const float cross = a.x() * b.y() - a.y() * b.x();
    const float dot = a.x() * b.x() + a.y() * b.y();
    return std::atan2(std::abs(cross), std::abs(dot)) * 180.0f / std::numbers::pi_v<float>;
  }

  /// Moves each track with `motion`: its point, its axis (through two points half a window
  /// either side, so a rotation or a perspective turns it) and its window length. Every track
  /// ages one frame.
  void predict(const camera_motion& motion) noexcept {
    for (std::size_t i = 0; i < count_; ++i) {
      perch_track& t = tracks_[i];
      ++t.age;
      const float half = std::max(t.window_px, 2.0f) * 0.5f;
      const point2f a = motion.apply(t.position_px - half * t.axis);
      const point2f b = motion.apply(t.position_px + half * t.axis);
      const point2f p = motion.apply(t.position_px);
      const point2f d = b - a;
      const float n = d.norm();
      const float window = t.window_px * (n / (2.0f * half));
      const float scale = motion.scale_at(t.position_px);
      // A motion that sends the track to infinity or flattens the picture there (a huge or
      // projective one) leaves it where it was: it ages and is lost rather than carry a
      // position no site can match.
      if (p.allFinite() && n > 0 && std::isfinite(n) && std::isfinite(window) && scale > 0 &&
          std::isfinite(scale)) {
        t.position_px = p;
        t.axis = d / n;
        t.window_px = window;
        t.heading_deg = heading_deg(t.axis);
        // z's relative variance grows by the motion's and the drift's (at most 1: 100 %).
        const float u = t.depth_uncertainty, m = motion.scale_uncertainty, q = options_.depth_drift;
        t.depth_uncertainty = std::sqrt(std::min(u * u + m * m + q * q, 1.0f));
        const float z = t.position_m.z() / scale;
        place(t, std::isfinite(z) ? z : t.position_m.z());
      }
      t.matched = false;
      t.measured = false;
    }
  }

  /// Puts track `t`'s metric position at its pixel, `z_m` metres deep (with the camera, once
  /// a frame gave the track depth).
  void place(perch_track& t, float z_m) const noexcept {
    if (!camera_ || !t.has_position) return;
    const point3f p = camera_->back_project(t.position_px, z_m);
    if (p.allFinite()) t.position_m = p;  // else an absurd depth (beyond 1e38 m): kept as it was
  }

  /// The relative standard uncertainty of a measured depth `z_m` metres: the frame's stated
  /// one and a depth image's rounding to whole millimetres (1/√12 mm RMS).
  [[nodiscard]] float depth_noise(float z_m) const noexcept {
    constexpr float rounding_m = 0.001f / 3.4641016f;
    const float rounding = z_m > 0 ? rounding_m / z_m : 1.0f;
    return std::min(std::hypot(frame_depth_uncertainty_, rounding), 1.0f);
  }

  /// Takes candidate `c`'s depth into track `t` (weighed against the prediction by their
  /// uncertainties, or as it is when the track had none) and places `t` at its pixel.
  void measure_depth(perch_track& t, const candidate& c) const noexcept {
    // A depth is in front of the camera: a point at or behind it is no measurement.
    t.measured = c.has_position && c.position_m.z() > 0;
    float z = t.position_m.z();
    if (t.measured) {
      t.measured_m = c.position_m;
      const float r = depth_noise(c.position_m.z());
      if (t.has_position) {
        const float p = t.depth_uncertainty * t.depth_uncertainty;
        const float gain = p + r * r > 0 ? p / (p + r * r) : 1.0f;
        z = blend(z, c.position_m.z(), gain);
        t.depth_uncertainty = std::sqrt((1.0f - gain) * p);
      } else {
        z = c.position_m.z();
        t.depth_uncertainty = r;
      }
      t.has_position = camera_.has_value();
    }
    place(t, z);
  }

  /// A window with every measure the tracker smooths finite: anything else (a result not from
  /// `find_perch`, or corrupted) would poison a track's smoothed values for good.
  [[nodiscard]] static bool usable(const window_measures& w, float penalty) noexcept {
    for (const float v : {w.heading_deg, w.slope_deg, w.claw_diameter_mm, penalty})
      if (!std::isfinite(v)) return false;
    return true;
  }

  void add_candidate(const window_measures& w, float penalty, const near_miss* failed) noexcept {
    if (candidate_count_ == max_candidates || !usable(w, penalty)) return;
    const point2f base = to_point(w.base_end), tip = to_point(w.tip_end);
    point2f axis = tip - base;
    float length = axis.norm();
    if (length > 0) {
      axis /= length;
    } else {  // a one-point window: its heading only
      const float a = w.heading_deg * std::numbers::pi_v<float> / 180.0f;
      axis = point2f(std::cos(a), -std::sin(a));
      length = 1.0f;
    }
    if (!axis.allFinite()) return;  // a heading too large for its cosine to mean anything
    candidate& c = candidates_[candidate_count_++];
    const bool has_position = w.has_position && w.position_m.allFinite();
    c = {to_point(w.centre), axis, length, w.heading_deg, w.slope_deg, w.claw_diameter_mm, penalty,
         w.position_m, has_position, failed == nullptr, {}, {}, 0, 0, -1};
    if (failed == nullptr) return;
    c.constraint = failed->constraint;
    c.unit = failed->unit;
    c.miss = failed->miss;
    c.noise = measurement_noise(failed->constraint, failed->unit, w.mm_per_px);
  }

  void gather_candidates(const perch_result& frame) noexcept {
    candidate_count_ = 0;
    offered_ = 0;
    frame_depth_uncertainty_ = std::isfinite(frame.scale_uncertainty)
                                   ? std::min(std::abs(frame.scale_uncertainty), 1.0f)
                                   : 1.0f;
    for (const perch_site& s : frame.sites) {
      ++offered_;
      add_candidate(s.window, s.penalty, nullptr);
    }
    for (const near_miss& m : frame.near_misses) {
      if (!m.present) continue;
      ++offered_;
      add_candidate(m.window, 1.0f, &m);
    }
  }

  /// The cost of matching track `t` to candidate `c`, or a negative number when gated out.
  [[nodiscard]] float match_cost(const perch_track& t, const candidate& c) const noexcept {
    const float window = std::max(t.window_px, 1.0f);
    const point2f d = c.position - t.position_px;
    const float along = d.dot(t.axis) / (options_.along_gate_windows * window);
    const float across = (t.axis.x() * d.y() - t.axis.y() * d.x()) /
                         (options_.across_gate_windows * window);
    const float angle = axis_angle_deg(t.axis, c.axis) / options_.axis_gate_deg;
    if (!(std::abs(along) <= 1 && std::abs(across) <= 1 && angle <= 1)) return -1;
    const float cost = along * along + across * across + angle * angle;
    if (c.feasible) return cost;
    // A near miss is one window failing one rule, the closest such window: it speaks for the
    // track's own spot only, and a feasible site within the gate is the better match.
    if (std::abs(along) * options_.along_gate_windows > near_miss_reach_windows) return -1;
    return cost + 3.0f;
  }

  /// Greedy assignment: every gated pair, cheapest first; a track and a candidate take part in
  /// one match at most.
  void associate() noexcept {
    std::size_t n = 0;
    for (std::size_t t = 0; t < count_; ++t)
      for (std::size_t c = 0; c < candidate_count_; ++c) {
        const float cost = match_cost(tracks_[t], candidates_[c]);
        if (cost >= 0)
          pairs_[n++] = {cost, static_cast<std::uint16_t>(t), static_cast<std::uint16_t>(c)};
      }
    std::sort(pairs_.begin(), pairs_.begin() + static_cast<std::ptrdiff_t>(n),
              [](const pair_cost& a, const pair_cost& b) {
                if (a.cost != b.cost) return a.cost < b.cost;
                if (a.track != b.track) return a.track < b.track;
                return a.cand < b.cand;
              });
    for (std::size_t i = 0; i < n; ++i) {
      perch_track& t = tracks_[pairs_[i].track];
      candidate& c = candidates_[pairs_[i].cand];
      if (t.matched || c.track >= 0) continue;
      t.matched = true;
      c.track = pairs_[i].track;
    }
  }

  [[nodiscard]] static float blend(float old_value, float new_value, float gain) noexcept {
    return old_value + gain * (new_value - old_value);
  }

  /// Smooths track `t` toward candidate `c`: across and along the limb with their own gains.
  void absorb(perch_track& t, const candidate& c) noexcept {
    const point2f d = c.position - t.position_px;
    const point2f normal(-t.axis.y(), t.axis.x());
    t.position_px += options_.along_gain * d.dot(t.axis) * t.axis +
                     options_.across_gain * d.dot(normal) * normal;
    const point2f measured = c.axis.dot(t.axis) < 0 ? point2f(-c.axis) : c.axis;
    const point2f axis = t.axis + options_.measure_gain * (measured - t.axis);
    if (axis.norm() > 0) t.axis = axis.normalized();
    t.heading_deg = heading_deg(t.axis);
    t.window_px = blend(t.window_px, c.window_px, options_.measure_gain);
    t.slope_deg = blend(t.slope_deg, c.slope_deg, options_.measure_gain);
    t.diameter_mm = blend(t.diameter_mm, c.diameter_mm, options_.measure_gain);
    if (c.feasible) t.penalty = blend(t.penalty, c.penalty, options_.measure_gain);
    measure_depth(t, c);
    t.feasible = c.feasible;
    t.failed_constraint = c.constraint;
    t.failed_unit = c.unit;
    t.failed_by = c.miss;
    t.marginal = !c.feasible && c.miss <= c.noise;  // false for a NaN miss
    t.infeasible_streak = c.feasible ? 0 : t.infeasible_streak + 1;
    ++t.hits;
    ++t.streak;
    t.misses = 0;
    if (t.state == track_state::lost ||
        (t.state == track_state::tentative && t.streak >= options_.confirm_frames))
      t.state = track_state::confirmed;
  }

  [[nodiscard]] perch_track open_track(const candidate& c) noexcept {
    perch_track t;
    t.id = next_id_++;
    t.position_px = c.position;
    t.axis = c.axis;
    t.window_px = c.window_px;
    t.heading_deg = heading_deg(c.axis);
    t.slope_deg = c.slope_deg;
    t.diameter_mm = c.diameter_mm;
    t.penalty = c.penalty;
    measure_depth(t, c);
    t.hits = t.streak = 1;
    t.matched = true;
    t.state = options_.confirm_frames <= 1 ? track_state::confirmed : track_state::tentative;
    return t;
  }

  /// Applies the matches and opens tentative tracks on unmatched feasible sites (a full table
  /// gives up its oldest lost track first). Returns how many sites found no room.
  std::uint32_t apply_matches() noexcept {
    for (std::size_t c = 0; c < candidate_count_; ++c)
      if (candidates_[c].track >= 0)
        absorb(tracks_[static_cast<std::size_t>(candidates_[c].track)], candidates_[c]);
    std::uint32_t unplaced = 0;
    for (std::size_t c = 0; c < candidate_count_; ++c) {
      const candidate& cand = candidates_[c];
      if (cand.track >= 0 || !cand.feasible) continue;
      if (count_ == max_tracks && !drop_one_lost_track()) {
        ++unplaced;
        continue;
      }
      tracks_[count_++] = open_track(cand);
    }
    return unplaced + static_cast<std::uint32_t>(offered_ - candidate_count_);
  }

  /// Frees the slot of the lost track unseen longest (never the target). False when none.
  bool drop_one_lost_track() noexcept {
    std::size_t worst = count_;
    for (std::size_t i = 0; i < count_; ++i) {
      const perch_track& t = tracks_[i];
      if (t.state == track_state::lost && t.id != target_id_ &&
          (worst == count_ || t.misses > tracks_[worst].misses))
        worst = i;
    }
    if (worst == count_) return false;
    remove_at(worst);
    return true;
  }

  void remove_at(std::size_t i) noexcept {
    for (std::size_t j = i + 1; j < count_; ++j) tracks_[j - 1] = tracks_[j];
    --count_;
  }

  /// Unmatched tracks: a miss; lost after `drop_frames`, forgotten `forget_frames` later (a
  /// tentative track at its first miss).
  void age_unmatched() noexcept {
    for (std::size_t i = 0; i < count_;) {
      perch_track& t = tracks_[i];
      if (!t.matched) {
        ++t.misses;
        t.streak = 0;
        t.better_streak = 0;
        if (t.state == track_state::confirmed && t.misses >= options_.drop_frames)
          t.state = track_state::lost;
        const bool forget = t.state == track_state::tentative ||
                            (t.state == track_state::lost &&
                             t.misses >= options_.drop_frames + options_.forget_frames);
        if (forget && t.id != target_id_) {
          remove_at(i);
          continue;
        }
      }
      ++i;
    }
  }

  /// A frame with nothing to match: tracks move with `motion` and take a miss.
  [[nodiscard]] tracking_result coast(tracking_status why, const camera_motion& motion) noexcept {
    predict(motion);
    candidate_count_ = 0;
    offered_ = 0;
    age_unmatched();
    return finish(why, 0);
  }

  [[nodiscard]] perch_track* find(std::uint32_t id) noexcept {
    for (std::size_t i = 0; i < count_; ++i)
      if (tracks_[i].id == id) return &tracks_[i];
    return nullptr;
  }

  [[nodiscard]] static bool eligible(const perch_track& t) noexcept {
    return t.state == track_state::confirmed && t.feasible && t.misses == 0;
  }

  /// The eligible track with the lowest smoothed penalty (ties: the lower id), or null.
  [[nodiscard]] perch_track* best_eligible(std::uint32_t except) noexcept {
    perch_track* best = nullptr;
    for (std::size_t i = 0; i < count_; ++i) {
      perch_track& t = tracks_[i];
      if (t.id == except || !eligible(t)) continue;
      if (best == nullptr || t.penalty < best->penalty) best = &t;
    }
    return best;
  }

  /// Whether the target's site has failed a rule for too long, and then why: beyond the rule's
  /// measurement noise for `infeasible_frames` near-miss frames in a row, within it (every
  /// frame of the streak counts, whatever its miss) for `doubtful_frames`.
  [[nodiscard]] bool failed_too_long(const perch_track& t, target_change& change) const noexcept {
    const std::uint32_t limit = t.marginal ? options_.doubtful_frames : options_.infeasible_frames;
    if (t.feasible || t.infeasible_streak < limit) return false;
    change.reason = t.marginal ? target_change_reason::doubtful : target_change_reason::infeasible;
    change.constraint = t.failed_constraint;
    change.unit = t.failed_unit;
    change.miss = t.failed_by;
    change.frames = t.infeasible_streak;
    return true;
  }

  /// Keeps the target or changes it, saying why; `change` is filled when it changed.
  bool choose_target(target_change& change) noexcept {
    const bool changed = retarget(change);
    for (std::size_t i = 0; i < count_; ++i)
      tracks_[i].doubtful =
          tracks_[i].id == target_id_ && (!tracks_[i].feasible || tracks_[i].misses > 0);
    return changed;
  }

  bool retarget(target_change& change) noexcept {
    perch_track* target = find(target_id_);
    bool leave = false;
    if (target != nullptr && target->state == track_state::lost) {
      change.reason = target_change_reason::lost;
      leave = true;
    } else if (target != nullptr && failed_too_long(*target, change)) {
      leave = true;
    } else if (target == nullptr && target_id_ != 0) {
      change.reason = target_change_reason::lost;
      leave = true;
    }
    if (target != nullptr && !leave) return challenge(*target, change);
    if (target_id_ == 0) change.reason = target_change_reason::acquired;
    perch_track* next = best_eligible(target_id_);
    if (next == nullptr) {
      if (!leave) return false;  // no target, none eligible: nothing changes
      change.from = target_id_;
      change.to = 0;
      target_id_ = 0;
      return true;
    }
    change.from = target_id_;
    change.to = next->id;
    target_id_ = next->id;
    for (std::size_t i = 0; i < count_; ++i) tracks_[i].better_streak = 0;
    return true;
  }

  /// Counts, for each eligible track, the frames in a row it beat the target by the margin;
  /// the first to hold it for `switch_frames` (lowest penalty among them) takes over.
  bool challenge(perch_track& target, target_change& change) noexcept {
    perch_track* winner = nullptr;
    for (std::size_t i = 0; i < count_; ++i) {
      perch_track& t = tracks_[i];
      if (t.id == target.id) continue;
      const bool beats = eligible(t) && t.penalty < target.penalty - options_.switch_margin;
      t.better_streak = beats ? t.better_streak + 1 : 0;
      if (t.better_streak >= options_.switch_frames &&
          (winner == nullptr || t.penalty < winner->penalty))
        winner = &t;
    }
    if (winner == nullptr) return false;
    change = {target.id, winner->id, target_change_reason::better, {}, {}, 0, 0};
    target_id_ = winner->id;
    for (std::size_t i = 0; i < count_; ++i) tracks_[i].better_streak = 0;
    return true;
  }

  [[nodiscard]] tracking_result finish(tracking_status why, std::uint32_t unplaced) noexcept {
    tracking_result out;
    out.status = why;
    out.frame = frame_;
    if (why == tracking_status::invalid_options) return out;
    ++frame_;
    out.changed = choose_target(out.change);
    out.tracks = tracks();
    out.target = find(target_id_);
    out.candidates = offered_;
    out.unplaced = unplaced;
    return out;
  }

  tracker_options options_;
  std::optional<pinhole> camera_;
  bool options_ok_ = false;
  std::array<perch_track, max_tracks> tracks_{};
  std::size_t count_ = 0;
  std::array<candidate, max_candidates> candidates_{};
  std::size_t candidate_count_ = 0;
  std::uint32_t offered_ = 0;
  std::array<pair_cost, max_tracks * max_candidates> pairs_{};
  std::uint32_t next_id_ = 1;
  std::uint32_t target_id_ = 0;
  std::uint32_t frame_ = 0;
  int width_ = 0, height_ = 0;
  float frame_depth_uncertainty_ = 0;  ///< this frame's `scale_uncertainty`, for its depths
};

}  // namespace perch
