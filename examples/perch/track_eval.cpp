// SPDX-License-Identifier: BSL-1.0
// perch eval --sequences N: the tracker on synthetic approach sequences (support/sequence.hpp),
// each frame's target judged by the frame's truth: on a feasible stretch, switches the truth
// does not call for, jitter of the target against the tree, frames to lock; with --depth, the
// error of its metric position.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "perch/track.hpp"
#include "support/json_writer.hpp"
#include "support/parallel_for.hpp"
#include "support/progress.hpp"
#include "support/sequence.hpp"
#include "tool.hpp"

namespace perch::tool {
namespace {

namespace st = perch::support;

/// Where the tracker's motion comes from.
enum class motion_source : std::uint8_t { truth, none, estimated };

/// How the target of a frame was matched, for the frames it is on no feasible stretch.
enum class target_match : std::uint8_t { site, near_miss, unmatched };
constexpr int target_match_count = 3;
constexpr int verdict_count = static_cast<int>(st::window_verdict::bending) + 1;
constexpr int reason_count = static_cast<int>(target_change_reason::doubtful) + 1;

/// Where the frames whose target is not on a feasible stretch went (the measure the tracker's
/// changes are decided on): no target at all, or a confident wrong target, the worst case.
struct miss_breakdown {
  int unlocked = 0;  ///< a feasible stretch in view, no target yet in this sequence
  int dropped = 0;   ///< a feasible stretch in view, no target, after a target was given up
  int wrong_in_view = 0;  ///< a feasible stretch in view, the target on none
  int wrong_no_view = 0;  ///< no feasible stretch anywhere in the frame, a target all the same
  int wrong_doubtful = 0;  ///< of the wrong frames (both kinds), those whose target was doubtful
  int wrong_by_match[target_match_count] = {};  ///< wrong frames by the target's match
  int wrong_by_verdict[verdict_count] = {};  ///< by the truth's verdict at the target's spot
  int doubtful_frames = 0;  ///< frames whose target was doubtful (kept through a near miss, or unseen)

  void add(const miss_breakdown& o) {
    unlocked += o.unlocked;
    dropped += o.dropped;
    wrong_in_view += o.wrong_in_view;
    wrong_no_view += o.wrong_no_view;
    wrong_doubtful += o.wrong_doubtful;
    doubtful_frames += o.doubtful_frames;
    for (int k = 0; k < target_match_count; ++k) wrong_by_match[k] += o.wrong_by_match[k];
    for (int k = 0; k < verdict_count; ++k) wrong_by_verdict[k] += o.wrong_by_verdict[k];
  }
};

/// One kind of metric point of the target (`position_m` or `measured_m`) against the truth, one
/// entry per frame that had it.
struct metric_errors {
  std::vector<float> error_mm;        ///< 3-D distance from the truth's point
  std::vector<float> error_percent;   ///< that, per cent of the truth point's distance from the camera
  std::vector<float> z_error_mm;      ///< depth alone, signed: the point's z − the truth's

  void add(const point3f& got_m, const point3f& truth_m) {
    const point3f error_m = got_m - truth_m;
    error_mm.push_back(1e3f * error_m.norm());
    error_percent.push_back(100.0f * error_m.norm() / truth_m.norm());
    z_error_mm.push_back(1e3f * error_m.z());
  }
  void add(const metric_errors& o) {
    error_mm.insert(error_mm.end(), o.error_mm.begin(), o.error_mm.end());
    error_percent.insert(error_percent.end(), o.error_percent.begin(), o.error_percent.end());
    z_error_mm.insert(z_error_mm.end(), o.z_error_mm.begin(), o.z_error_mm.end());
  }
};

/// What `metric_errors` sum up to.
struct metric_summary {
  std::size_t frames = 0;
  double rms_mm = 0, p95_mm = 0, rms_percent = 0, p95_percent = 0, z_mean_mm = 0, z_rms_mm = 0;
};

double rms(const std::vector<float>& v) {
  double sq = 0;
  for (const float x : v) sq += static_cast<double>(x) * static_cast<double>(x);
  return v.empty() ? 0.0 : std::sqrt(sq / static_cast<double>(v.size()));
}

double mean(const std::vector<float>& v) {
  return v.empty() ? 0.0 : std::accumulate(v.begin(), v.end(), 0.0) / static_cast<double>(v.size());
}

metric_summary summarise(const metric_errors& e) {
  return {.frames = e.error_mm.size(),
          .rms_mm = rms(e.error_mm),
          .p95_mm = static_cast<double>(percentile(e.error_mm, 0.95)),
          .rms_percent = rms(e.error_percent),
          .p95_percent = static_cast<double>(percentile(e.error_percent, 0.95)),
          .z_mean_mm = mean(e.z_error_mm),
          .z_rms_mm = rms(e.z_error_mm)};
}

/// What one sequence scored.
struct sequence_score {
  int index = 0;
  int frames = 0;
  int feasible_frames = 0;    ///< frames whose truth has a feasible stretch
  int on_feasible = 0;        ///< of those, frames whose target is on one
  int raw_on_feasible = 0;    ///< of those, frames whose best single-frame site is on one
  int target_frames = 0;      ///< frames with a target
  int switches = 0;           ///< target changes away from a target
  int unwarranted = 0;        ///< of those, the old target still on a feasible stretch in view
  int by_reason[reason_count] = {};  ///< unwarranted switches by `target_change_reason`
  int lock_frames = -1;       ///< first feasible view → first target on a feasible stretch
  double jitter_sq_sum = 0;   ///< Σ (deviation / local diameter)²
  int jitter_samples = 0;
  miss_breakdown misses;
  metric_errors position;     ///< with --depth: the target's `position_m` (tracked, smoothed)
  metric_errors measured;     ///< and its `measured_m` (the frame's own)
  int frames_without_depth = 0;  ///< with --depth: frames whose depth had no sample on the tree
  float tracker_ms = 0;       ///< tracker time over the sequence (motion estimate included)
  std::string error;
};

/// A point is on a feasible stretch within 3 px + 3 % of the window (as `perch eval`).
bool on_feasible(const st::perch_truth& truth, point2f p) {
  return truth.has_perch() && truth.is_feasible_site(p, 3.0f + 0.03f * truth.window_px());
}

bool inside(const st::sequence_frame& f, point2f p) {
  return p.x() >= 0 && p.y() >= 0 && p.x() < static_cast<float>(f.mask.width()) &&
         p.y() < static_cast<float>(f.mask.height());
}

/// One target run's positions, in world pixels, and the frames they came from.
struct target_run {
  std::uint32_t id = 0;
  std::vector<point2f> world;
  std::vector<float> diameter_world_px;
};

/// Adds a run's jitter: each position's distance from the run's mean, over the local diameter.
void add_jitter(const target_run& run, sequence_score& score) {
  if (run.world.size() < 2) return;
  point2f mean = point2f::Zero();
  for (const point2f& p : run.world) mean += p;
  mean /= static_cast<float>(run.world.size());
  for (std::size_t k = 0; k < run.world.size(); ++k) {
    const float d = run.diameter_world_px[k];
    if (!(d > 0)) continue;
    const double r = static_cast<double>((run.world[k] - mean).norm() / d);
    score.jitter_sq_sum += r * r;
    ++score.jitter_samples;
  }
}

std::int64_t now_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

/// How the target was matched in this frame.
target_match match_of(const perch_track& t) {
  if (!t.matched) return target_match::unmatched;
  return t.feasible ? target_match::site : target_match::near_miss;
}

/// The truth's verdict at the window centred where `p` lies on the tree (not twigs).
st::window_verdict verdict_at(const st::sequence_frame& frame, const st::perch_truth& truth,
                              point2f p) {
  const st::limb_location at = st::locate(frame.tree.limbs, p, st::limb_set::without_twigs);
  if (at.limb < 0) return st::window_verdict::off_limb;
  return truth.window(at.limb, at.arc_px).verdict;
}

/// Books a frame that has a feasible stretch in view but a target on none, or no target.
void judge_miss(const st::sequence_frame& frame, const st::perch_truth& truth,
                const tracking_result& r, bool ever_targeted, miss_breakdown& m) {
  const bool view = truth.has_perch();
  if (r.target == nullptr) {
    if (view) ++(ever_targeted ? m.dropped : m.unlocked);
    return;
  }
  const perch_track& t = *r.target;
  if (t.doubtful) ++m.doubtful_frames;
  if (view && on_feasible(truth, t.position_px)) return;
  ++(view ? m.wrong_in_view : m.wrong_no_view);
  if (t.doubtful) ++m.wrong_doubtful;
  ++m.wrong_by_match[static_cast<int>(match_of(t))];
  ++m.wrong_by_verdict[static_cast<int>(verdict_at(frame, truth, t.position_px))];
}

/// The frame's target against its truth: on a feasible stretch, lock, jitter run.
void judge_target(const st::sequence_frame& frame, const st::perch_truth& truth,
                  const tracking_result& r, int f, int first_feasible, target_run& run,
                  sequence_score& score) {
  ++score.target_frames;
  const point2f p = r.target->position_px;
  const bool good = truth.has_perch() && on_feasible(truth, p);
  if (good) ++score.on_feasible;
  if (good && score.lock_frames < 0) score.lock_frames = f - first_feasible;
  if (r.target->id != run.id) {
    add_jitter(run, score);
    run = target_run{r.target->id, {}, {}};
  }
  const camera_motion to_world = st::detail::sequences::inverse_similarity(frame.from_world);
  const st::limb_location at = st::locate(frame.tree, p, st::limb_set::without_twigs);
  run.world.push_back(to_world.apply(p));
  run.diameter_world_px.push_back(at.diameter_px / frame.scale);
}

/// With --depth: the target's metric points against the truth's point of the same pixel, the
/// truth limb centreline point nearest it on the tree's plane at its true distance (the pixel
/// of `measured_m` is its projection: the site's own, not the track's smoothed one).
void judge_metric(const st::approach_sequence& seq, const st::sequence_frame& frame, const perch_track& t,
                  sequence_score& score) {
  const auto truth_m = [&](point2f p) {
    return seq.point_m(frame, st::locate(frame.tree, p, st::limb_set::without_twigs).closest);
  };
  if (t.has_position) score.position.add(t.position_m, truth_m(t.position_px));
  if (t.measured) score.measured.add(t.measured_m, truth_m(seq.camera().project(t.measured_m)));
}

/// A switch away from a target is called for when the old target (moved with the camera) left
/// the view or its stretch.
void judge_switch(const st::sequence_frame& frame, const st::perch_truth& truth,
                  const tracking_result& r, bool had_target, point2f last_target,
                  sequence_score& score) {
  if (!r.changed || r.change.from == 0) return;
  ++score.switches;
  const point2f old = frame.motion.apply(last_target);
  if (had_target && inside(frame, old) && on_feasible(truth, old)) {
    ++score.unwarranted;
    ++score.by_reason[static_cast<int>(r.change.reason)];
  }
}

/// What a run of the evaluation varies.
struct eval_setup {
  st::sequence_options sequence;
  st::tree_family family = st::tree_family::arcs;
  motion_source source = motion_source::truth;
  tracker_options tracker;
  bool depth = false;  ///< --depth: each frame analysed with its depth, the tracker given the camera
};

/// A frame's analysis options: its true roll and scale (as `perch track --roll-csv
/// --scale-csv` gives them from the sequence's camera.csv).
run_config frame_config(const st::sequence_frame& frame) {
  run_config config;
  config.roll_deg = frame.roll_deg;
  config.scale.kind = scale_kind::fixed;
  config.scale.mm_per_px = frame.tree.mm_per_px;
  return config;
}

/// `config` with the frame's depth image and the sequence's camera as its scale: what `perch
/// synth --sequence --depth` writes and `perch track --depth-dir` reads, kept in memory.
run_config with_depth(run_config config, const st::approach_sequence& seq, const st::sequence_frame& frame) {
  config.scale.kind = scale_kind::depth;
  config.scale.depth_mm = seq.depth_mm(frame);
  config.scale.intrinsics = seq.camera();
  return config;
}

sequence_score score_sequence(int index, const eval_setup& setup, workspace& ws) {
  sequence_score score;
  score.index = index;
  const st::approach_sequence seq = st::evaluation_sequence(index, setup.sequence, setup.family);
  const motion_source source = setup.source;
  perch_tracker tracker(setup.tracker, setup.depth ? std::optional(seq.camera()) : std::nullopt);
  motion_estimator estimator;
  target_run run;
  point2f last_target = point2f::Zero();
  bool had_target = false, ever_targeted = false;
  int first_feasible = -1;
  std::int64_t tracker_ns = 0;
  for (int f = 0; f < seq.frames(); ++f) {
    const st::sequence_frame frame = seq.frame(f);
    const st::perch_truth truth(frame.tree, st::spec_for(frame));
    const run_config config = frame_config(frame);
    const std::optional<run_config> depth =
        setup.depth ? std::optional(with_depth(config, seq, frame)) : std::nullopt;
    bool depth_dropped = false;
    const auto found =
        find_in_frame(frame.mask, config, depth ? &*depth : nullptr, ws, depth_dropped);
    score.frames_without_depth += depth_dropped ? 1 : 0;
    if (!found) {
      score.error = describe(found.error());
      return score;
    }
    const std::int64_t t0 = now_ns();
    const camera_motion motion = source == motion_source::truth ? frame.motion
                                 : source == motion_source::estimated
                                     ? estimator.update(*found).motion
                                     : camera_motion::identity();
    const tracking_result r = tracker.update(*found, motion);
    tracker_ns += now_ns() - t0;

    ++score.frames;
    if (truth.has_perch()) {
      ++score.feasible_frames;
      if (first_feasible < 0) first_feasible = f;
      if (!found->sites.empty() && on_feasible(truth, to_point(found->sites.front().window.centre)))
        ++score.raw_on_feasible;
    }
    judge_switch(frame, truth, r, had_target, last_target, score);
    judge_miss(frame, truth, r, ever_targeted, score.misses);
    had_target = r.target != nullptr;
    if (!had_target) continue;
    judge_target(frame, truth, r, f, first_feasible, run, score);
    if (setup.depth) judge_metric(seq, frame, *r.target, score);
    last_target = r.target->position_px;
    ever_targeted = true;
  }
  add_jitter(run, score);
  score.tracker_ms = static_cast<float>(static_cast<double>(tracker_ns) * 1e-6);
  return score;
}

struct totals {
  int sequences = 0, frames = 0, feasible = 0, on = 0, raw_on = 0, switches = 0, unwarranted = 0;
  int by_reason[reason_count] = {};
  miss_breakdown misses;
  metric_errors position, measured;
  int frames_without_depth = 0;
  double jitter_sq = 0;
  int jitter_n = 0;
  std::vector<int> locks;  ///< per sequence with a feasible view; -1: never locked
  double tracker_ms = 0;
  int errors = 0;
};

totals add_up(const std::vector<sequence_score>& scores) {
  totals t;
  for (const sequence_score& s : scores) {
    if (!s.error.empty()) {
      ++t.errors;
      continue;
    }
    ++t.sequences;
    t.frames += s.frames;
    t.feasible += s.feasible_frames;
    t.on += s.on_feasible;
    t.raw_on += s.raw_on_feasible;
    t.switches += s.switches;
    t.unwarranted += s.unwarranted;
    for (int k = 0; k < reason_count; ++k) t.by_reason[k] += s.by_reason[k];
    t.misses.add(s.misses);
    t.position.add(s.position);
    t.measured.add(s.measured);
    t.frames_without_depth += s.frames_without_depth;
    t.jitter_sq += s.jitter_sq_sum;
    t.jitter_n += s.jitter_samples;
    t.tracker_ms += static_cast<double>(s.tracker_ms);
    if (s.feasible_frames > 0) t.locks.push_back(s.lock_frames);
  }
  return t;
}

double percent(int a, int b) { return b > 0 ? 100.0 * a / b : 0.0; }

/// (a) no target, (b) a target on no feasible stretch, by match and by the truth's verdict.
void print_breakdown(const totals& t) {
  const miss_breakdown& m = t.misses;
  const int wrong = m.wrong_in_view + m.wrong_no_view;
  std::printf("frames with a feasible stretch and no target on one: %d\n", t.feasible - t.on);
  std::printf("  (a) no target: %d before the first lock, %d after a target was given up\n",
              m.unlocked, m.dropped);
  std::printf("  (b) a target on no feasible stretch: %d (and %d frames whose truth has no feasible "
              "stretch at all)\n", m.wrong_in_view, m.wrong_no_view);
  std::printf("      of those %d: confident (not flagged doubtful) %d, doubtful %d\n", wrong,
              wrong - m.wrong_doubtful, m.wrong_doubtful);
  std::printf("      by the target's match: ranked site %d, near miss %d, unmatched %d\n",
              m.wrong_by_match[static_cast<int>(target_match::site)],
              m.wrong_by_match[static_cast<int>(target_match::near_miss)],
              m.wrong_by_match[static_cast<int>(target_match::unmatched)]);
  std::printf("      by the truth's verdict at the target's spot:");
  for (int k = 0; k < verdict_count; ++k)
    if (m.wrong_by_verdict[k] > 0)
      std::printf(" %s %d", st::to_string(static_cast<st::window_verdict>(k)), m.wrong_by_verdict[k]);
  std::printf("\n  frames with a doubtful target: %d\n", m.doubtful_frames);
}

/// With --depth: the target's metric error, tracked and the frame's own.
void print_metric(const totals& t) {
  std::printf("metric target (with depth), against the truth's point (the limb centreline point nearest the\n"
              "  target's pixel, at the tree's true distance); %% of the distance from the camera:\n");
  for (const auto& [name, errors] : {std::pair{"position_m (tracked)    ", &t.position},
                                     std::pair{"measured_m (frame's own)", &t.measured}}) {
    const metric_summary m = summarise(*errors);
    std::printf("  %s %zu frames: 3-D RMS %.2f mm, 95th percentile %.2f mm (RMS %.3f %%, 95th %.3f %%); "
                "z mean %+.2f mm, RMS %.2f mm\n",
                name, m.frames, m.rms_mm, m.p95_mm, m.rms_percent, m.p95_percent, m.z_mean_mm, m.z_rms_mm);
  }
  if (t.frames_without_depth > 0)
    std::printf("  frames whose depth had no sample on the tree (analysed with the true scale): %d\n",
                t.frames_without_depth);
}

void print_scores(const std::vector<sequence_score>& scores, const totals& t, bool rows, bool depth) {
  if (rows) {
    std::printf("%4s %6s %8s %9s %9s %8s %8s %7s %8s %7s %6s %8s", "seq", "frames", "feasible", "on (%)",
                "raw (%)", "switches", "unwarr.", "lock", "jitter/d", "no tgt", "wrong", "doubtful");
    if (depth) std::printf(" %8s %8s %9s", "pos (mm)", "z (mm)", "meas (mm)");
    std::printf("\n");
    for (const sequence_score& s : scores) {
      if (!s.error.empty()) {
        std::printf("%4d error: %s\n", s.index, s.error.c_str());
        continue;
      }
      std::printf("%4d %6d %8d %9.1f %9.1f %8d %8d %7d %8.3f %7d %6d %8d", s.index, s.frames,
                  s.feasible_frames, percent(s.on_feasible, s.feasible_frames),
                  percent(s.raw_on_feasible, s.feasible_frames), s.switches, s.unwarranted, s.lock_frames,
                  s.jitter_samples ? std::sqrt(s.jitter_sq_sum / s.jitter_samples) : 0.0,
                  s.misses.unlocked + s.misses.dropped, s.misses.wrong_in_view + s.misses.wrong_no_view,
                  s.misses.doubtful_frames);
      // RMS of the target's 3-D error and of its depth error, tracked; 3-D of the frame's own.
      if (depth)
        std::printf(" %8.2f %8.2f %9.2f", rms(s.position.error_mm), rms(s.position.z_error_mm),
                    rms(s.measured.error_mm));
      std::printf("\n");
    }
    std::printf("\n");
  }
  std::vector<int> locked;
  int never = 0;
  for (const int l : t.locks) (l < 0 ? ++never : (locked.push_back(l), 0));
  std::sort(locked.begin(), locked.end());
  const int within5 = static_cast<int>(std::count_if(locked.begin(), locked.end(), [](int l) { return l <= 5; }));
  std::printf("sequences %d, frames %d, frames with a feasible stretch %d\n", t.sequences, t.frames, t.feasible);
  std::printf("target on a feasible stretch: %.1f %% of those frames (best single-frame site: %.1f %%)\n",
              percent(t.on, t.feasible), percent(t.raw_on, t.feasible));
  std::printf("target switches: %d, of which the truth did not call for %d: %.2f per 100 frames\n",
              t.switches, t.unwarranted, t.frames ? 100.0 * t.unwarranted / t.frames : 0.0);
  std::printf("  unwarranted by the tracker's reason:");
  for (int k = 1; k < reason_count; ++k)
    std::printf(" %s %d", std::string(to_string(static_cast<target_change_reason>(k))).c_str(), t.by_reason[k]);
  std::printf("\n");
  print_breakdown(t);
  std::printf("jitter (RMS distance from the target run's mean point on the tree / local diameter): %.3f\n",
              t.jitter_n ? std::sqrt(t.jitter_sq / t.jitter_n) : 0.0);
  std::printf("frames to lock after the first feasible view: median %d, max %d, within 5 frames %d of %zu "
              "(never locked %d)\n",
              locked.empty() ? -1 : locked[locked.size() / 2], locked.empty() ? -1 : locked.back(), within5,
              t.locks.size(), never);
  if (depth) print_metric(t);
  std::printf("tracker time: %.4f ms per frame (beyond find_perch)\n",
              t.frames ? t.tracker_ms / t.frames : 0.0);
  if (t.errors) std::printf("errors: %d sequences\n", t.errors);
}

/// `"KEY": {frames, rms_mm, p95_mm, rms_percent, p95_percent, z_mean_mm, z_rms_mm}`.
void write_metric(st::json_writer& json, std::string_view key, const metric_errors& errors) {
  const metric_summary m = summarise(errors);
  json.key(key).begin_object()
      .key("frames").value(static_cast<std::int64_t>(m.frames))
      .key("rms_mm").value(m.rms_mm)
      .key("p95_mm").value(m.p95_mm)
      .key("rms_percent").value(m.rms_percent)
      .key("p95_percent").value(m.p95_percent)
      .key("z_mean_mm").value(m.z_mean_mm)
      .key("z_rms_mm").value(m.z_rms_mm)
      .end_object();
}

std::string json_of(const totals& t, int frames_per_sequence, std::string_view motion,
                    st::tree_family family, bool depth) {
  st::json_writer json;
  std::vector<int> locked;
  for (const int l : t.locks)
    if (l >= 0) locked.push_back(l);
  std::sort(locked.begin(), locked.end());
  json.begin_object()
      .key("sequences").value(static_cast<std::int64_t>(t.sequences))
      .key("frames_per_sequence").value(static_cast<std::int64_t>(frames_per_sequence))
      .key("motion").value(motion)
      .key("family").value(st::to_string(family))
      .key("frames").value(static_cast<std::int64_t>(t.frames))
      .key("feasible_frames").value(static_cast<std::int64_t>(t.feasible))
      .key("on_feasible_percent").value(percent(t.on, t.feasible))
      .key("raw_on_feasible_percent").value(percent(t.raw_on, t.feasible))
      .key("switches").value(static_cast<std::int64_t>(t.switches))
      .key("unwarranted_switches").value(static_cast<std::int64_t>(t.unwarranted))
      .key("unwarranted_per_100_frames").value(t.frames ? 100.0 * t.unwarranted / t.frames : 0.0)
      .key("jitter_per_diameter").value(t.jitter_n ? std::sqrt(t.jitter_sq / t.jitter_n) : 0.0)
      .key("lock_median_frames").value(static_cast<std::int64_t>(locked.empty() ? -1 : locked[locked.size() / 2]))
      .key("lock_max_frames").value(static_cast<std::int64_t>(locked.empty() ? -1 : locked.back()))
      .key("never_locked").value(static_cast<std::int64_t>(t.locks.size() - locked.size()))
      .key("no_target_before_lock_frames").value(static_cast<std::int64_t>(t.misses.unlocked))
      .key("no_target_after_drop_frames").value(static_cast<std::int64_t>(t.misses.dropped))
      .key("wrong_target_frames").value(static_cast<std::int64_t>(t.misses.wrong_in_view))
      .key("wrong_target_no_perch_frames").value(static_cast<std::int64_t>(t.misses.wrong_no_view))
      .key("confident_wrong_target_frames")
      .value(static_cast<std::int64_t>(t.misses.wrong_in_view + t.misses.wrong_no_view - t.misses.wrong_doubtful))
      .key("doubtful_target_frames").value(static_cast<std::int64_t>(t.misses.doubtful_frames));
  if (depth) {
    json.key("metric").begin_object();
    write_metric(json, "position_m", t.position);
    write_metric(json, "measured_m", t.measured);
    json.key("frames_without_depth").value(static_cast<std::int64_t>(t.frames_without_depth)).end_object();
  }
  json.end_object();
  return std::move(json).take();
}

/// Scores `count` sequences of `family` on `jobs` threads.
std::vector<sequence_score> score_family(std::size_t count, unsigned jobs, const eval_setup& setup, bool quiet) {
  const unsigned workers = st::worker_count(count, jobs);
  std::vector<std::unique_ptr<workspace>> spaces;
  for (unsigned w = 0; w < workers; ++w) spaces.push_back(std::make_unique<workspace>());
  st::progress_options progress_options;
  if (quiet) progress_options.display = st::progress_display::off;
  st::progress_bar progress(count, progress_options);
  std::vector<sequence_score> scores = st::parallel_map(count, jobs, [&](std::size_t i, unsigned worker) {
    sequence_score s = score_sequence(static_cast<int>(i), setup, *spaces[worker]);
    progress.tick();
    return s;
  });
  progress.finish();
  return scores;
}

/// `--family`: a comma-separated list of arcs, colonisation and sympodial; `both` is arcs and
/// colonisation, `all` the three. Empty when a name is none of these.
std::vector<st::tree_family> families_of(const std::string& names) {
  if (names == "both") return {st::tree_family::arcs, st::tree_family::colonisation};
  if (names == "all")
    return {st::tree_family::arcs, st::tree_family::colonisation, st::tree_family::sympodial};
  std::vector<st::tree_family> out;
  std::size_t from = 0;
  while (from <= names.size()) {
    const std::size_t comma = std::min(names.find(',', from), names.size());
    const std::optional<st::tree_family> family = st::family_named(names.substr(from, comma - from));
    if (!family) return {};
    out.push_back(*family);
    from = comma + 1;
  }
  return out;
}

/// `--json`: one object per family, or the one family's object.
std::string json_of(const std::vector<std::string>& objects) {
  if (objects.size() == 1) return objects.front();
  std::string out = "[";
  for (std::size_t i = 0; i < objects.size(); ++i) out += (i ? "," : "") + objects[i];
  return out + "]";
}

/// What `perch eval --sequences --help` says about the scores.
constexpr const char* eval_epilog =
      "find_perch gets each frame's true scale (fixed_scale) and roll (perch_options::camera).\n"
      "On a feasible stretch: within 3 px + 3 % of the window of a feasible window centre of the\n"
      "frame's truth. A switch away from a target is unwarranted when the old target, moved with\n"
      "the camera, is still in view and on a feasible stretch. Jitter: per run of one target id,\n"
      "the RMS distance of the target from the run's mean point (in the tree's own pixels) over\n"
      "the local truth diameter. Lock: frames from the first frame with a feasible stretch to the\n"
      "first frame whose target is on one. The frames with a feasible stretch whose target is on\n"
      "none are broken down into (a) no target and (b) a target on no feasible stretch (the\n"
      "worst case: a confident wrong target), by how the target was matched and by the truth's\n"
      "verdict at its spot.\n"
      "With --depth, each frame is analysed with the depth image perch synth --sequence --depth\n"
      "writes for it (depth_scale with the sequence's camera) and the tracker gets that camera;\n"
      "every frame whose target has position_m (and, apart, measured_m: the frame's own point)\n"
      "is scored against the truth's point: the limb centreline point nearest the target's pixel\n"
      "(for measured_m, its projection) back-projected at the tree's true distance. Reported: the\n"
      "RMS and 95th percentile of the 3-D error, in mm and in % of the truth point's distance\n"
      "from the camera, and the depth (z) error's mean and RMS; --rows adds each sequence's RMS\n"
      "3-D and z error of position_m, pos (mm) and z (mm), and the RMS 3-D error of measured_m.\n"
      "Example: perch eval --sequences 40 --frames 90 --family both --rows";

}  // namespace

int run_track_eval(int argc, const char* const* argv) {
  st::arg_parser args(
      "perch eval --sequences",
      "Runs find_perch and the tracker on N synthetic approach sequences (one tree of the\n"
      "population each, filmed approaching from 3x to 1x the distance with drift, roll, shake and\n"
      "segmentation noise) and scores the target against each frame's truth.");
  args.add_option("sequences", "N", "number of sequences (per family)", "40");
  args.add_option("frames", "F", "frames per sequence", "90");
  args.add_option("family", "F", "the population families: arcs, colonisation, sympodial (comma-separated),\n"
                                 "both (arcs,colonisation) or all", "arcs");
  args.add_option("motion", "SOURCE", "the tracker's camera motion: truth (as visual odometry would\n"
                                      "give it), estimated (from the masks: motion_estimator) or none (identity)", "truth");
  const tracker_options defaults;
  args.add_option("doubtful-frames", "N", "tracker_options::doubtful_frames: frames a target may stay\n"
                                          "while its spot misses a rule within the rule's noise",
                  std::to_string(defaults.doubtful_frames));
  args.add_option("infeasible-frames", "N", "tracker_options::infeasible_frames: near-miss frames beyond\n"
                                            "the rule's noise before the target is left",
                  std::to_string(defaults.infeasible_frames));
  args.add_option("jobs", "N", "worker threads; 0 = all cores", "0", 'j');
  args.add_option("json", "OUT.json", "also write the totals as JSON (an array with more than one family)");
  args.add_flag("rows", "one row per sequence");
  args.add_flag("depth", "analyse each frame with its depth and give the tracker the camera;\n"
                         "score the target's metric position (position_m, measured_m)");
  args.add_flag("quiet", "no progress bar");
  args.set_epilog(eval_epilog);
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "eval", exit)) return exit;
  const auto n = args.get_int("sequences", 40, 1, 100000);
  const auto frames = args.get_int("frames", 90, 2, 100000);
  const auto jobs = args.get_int("jobs", 0, 0, 1024);
  const auto doubtful = args.get_int("doubtful-frames", static_cast<int>(defaults.doubtful_frames), 1, 100000);
  const auto infeasible = args.get_int("infeasible-frames", static_cast<int>(defaults.infeasible_frames), 1, 100000);
  for (const auto* v : {&n, &frames, &jobs, &doubtful, &infeasible})
    if (!*v) {
      report_error("eval", v->error);
      return exit_usage;
    }
  const std::string motion = args.get_string("motion", "truth").value;
  if (motion != "truth" && motion != "none" && motion != "estimated") {
    report_error("eval", "--motion must be truth, estimated or none, not " + motion);
    return exit_usage;
  }
  const std::string family_name = args.get_string("family", "arcs").value;
  const std::vector<st::tree_family> families = families_of(family_name);
  if (families.empty()) {
    report_error("eval", "--family must name arcs, colonisation or sympodial (or be both or all), not " +
                             family_name);
    return exit_usage;
  }
  eval_setup setup;
  setup.source = motion == "truth"       ? motion_source::truth
                 : motion == "estimated" ? motion_source::estimated
                                         : motion_source::none;
  setup.sequence.frames = frames.value;
  setup.tracker.doubtful_frames = static_cast<std::uint32_t>(doubtful.value);
  setup.tracker.infeasible_frames = static_cast<std::uint32_t>(infeasible.value);
  setup.depth = args.flag("depth");
  std::vector<std::string> objects;
  int errors = 0;
  for (const st::tree_family family : families) {
    setup.family = family;
    const std::vector<sequence_score> scores =
        score_family(static_cast<std::size_t>(n.value), static_cast<unsigned>(jobs.value), setup, args.flag("quiet"));
    const totals t = add_up(scores);
    std::printf("perch eval --sequences: %d sequences of %d frames, %s family, motion %s%s\n\n", n.value,
                frames.value, std::string(st::to_string(family)).c_str(), motion.c_str(),
                setup.depth ? ", with depth" : "");
    print_scores(scores, t, args.flag("rows"), setup.depth);
    std::printf("\n");
    objects.push_back(json_of(t, frames.value, motion, family, setup.depth));
    errors += t.errors;
  }
  if (args.has("json"))
    if (const std::string e = write_text(std::string(*args.value("json")), json_of(objects)); !e.empty()) {
      report_error("eval", e);
      return exit_internal;
    }
  return errors > 0 ? exit_internal : exit_ok;
}

}  // namespace perch::tool
