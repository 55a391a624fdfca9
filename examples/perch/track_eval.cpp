// SPDX-License-Identifier: BSL-1.0
// perch eval --sequences N: the tracker on synthetic approach sequences (support/sequence.hpp),
// each frame's target judged by the frame's truth: on a feasible stretch, switches the truth
// does not call for, jitter of the target against the tree, frames to lock.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>
#include <numeric>
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
  int by_reason[4] = {0, 0, 0, 0};  ///< unwarranted switches by `target_change_reason`
  int lock_frames = -1;       ///< first feasible view → first target on a feasible stretch
  double jitter_sq_sum = 0;   ///< Σ (deviation / local diameter)²
  int jitter_samples = 0;
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

sequence_score score_sequence(int index, const st::sequence_options& options, motion_source source,
                              workspace& ws) {
  sequence_score score;
  score.index = index;
  const st::approach_sequence seq = st::evaluation_sequence(index, options);
  perch_tracker tracker;
  motion_estimator estimator;
  target_run run;
  point2f last_target = point2f::Zero();
  bool had_target = false;
  int first_feasible = -1;
  std::int64_t tracker_ns = 0;
  for (int f = 0; f < seq.frames(); ++f) {
    const st::sequence_frame frame = seq.frame(f);
    const st::perch_truth truth(frame.tree, st::spec_for(frame));
    perch_options o;
    o.camera = attitude{frame.roll_deg};
    const auto found = find_perch(frame.mask.view(), tendon_claw{}, fixed_scale{frame.tree.mm_per_px},
                                  ws, o);
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
    const bool feasible_view = truth.has_perch();
    if (feasible_view) {
      ++score.feasible_frames;
      if (first_feasible < 0) first_feasible = f;
      if (!found->sites.empty() && on_feasible(truth, to_point(found->sites.front().window.centre)))
        ++score.raw_on_feasible;
    }
    if (r.changed && r.change.from != 0) {
      ++score.switches;
      // Called for when the old target (moved with the camera) left the view or its stretch.
      const point2f old = frame.motion.apply(last_target);
      if (had_target && inside(frame, old) && on_feasible(truth, old)) {
        ++score.unwarranted;
        ++score.by_reason[static_cast<int>(r.change.reason)];
      }
    }
    const camera_motion to_world = st::detail::sequences::inverse_similarity(frame.from_world);
    if (r.target != nullptr) {
      ++score.target_frames;
      const point2f p = r.target->position_px;
      const bool good = feasible_view && on_feasible(truth, p);
      if (good) ++score.on_feasible;
      if (good && score.lock_frames < 0) score.lock_frames = f - first_feasible;
      if (r.target->id != run.id) {
        add_jitter(run, score);
        run = target_run{r.target->id, {}, {}};
      }
      const st::limb_location at = st::locate(frame.tree, p, st::limb_set::without_twigs);
      run.world.push_back(to_world.apply(p));
      run.diameter_world_px.push_back(at.diameter_px / frame.scale);
      last_target = p;
      had_target = true;
    } else {
      had_target = false;
    }
  }
  add_jitter(run, score);
  score.tracker_ms = static_cast<float>(static_cast<double>(tracker_ns) * 1e-6);
  return score;
}

struct totals {
  int sequences = 0, frames = 0, feasible = 0, on = 0, raw_on = 0, switches = 0, unwarranted = 0;
  int by_reason[4] = {0, 0, 0, 0};
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
    for (int k = 0; k < 4; ++k) t.by_reason[k] += s.by_reason[k];
    t.jitter_sq += s.jitter_sq_sum;
    t.jitter_n += s.jitter_samples;
    t.tracker_ms += static_cast<double>(s.tracker_ms);
    if (s.feasible_frames > 0) t.locks.push_back(s.lock_frames);
  }
  return t;
}

double percent(int a, int b) { return b > 0 ? 100.0 * a / b : 0.0; }

void print_scores(const std::vector<sequence_score>& scores, const totals& t, bool rows) {
  if (rows) {
    std::printf("%4s %6s %8s %9s %9s %8s %8s %7s %8s\n", "seq", "frames", "feasible", "on (%)",
                "raw (%)", "switches", "unwarr.", "lock", "jitter/d");
    for (const sequence_score& s : scores) {
      if (!s.error.empty()) {
        std::printf("%4d error: %s\n", s.index, s.error.c_str());
        continue;
      }
      std::printf("%4d %6d %8d %9.1f %9.1f %8d %8d %7d %8.3f\n", s.index, s.frames, s.feasible_frames,
                  percent(s.on_feasible, s.feasible_frames), percent(s.raw_on_feasible, s.feasible_frames),
                  s.switches, s.unwarranted, s.lock_frames,
                  s.jitter_samples ? std::sqrt(s.jitter_sq_sum / s.jitter_samples) : 0.0);
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
  std::printf("  unwarranted by the tracker's reason: lost %d, infeasible %d, better %d\n",
              t.by_reason[static_cast<int>(target_change_reason::lost)],
              t.by_reason[static_cast<int>(target_change_reason::infeasible)],
              t.by_reason[static_cast<int>(target_change_reason::better)]);
  std::printf("jitter (RMS distance from the target run's mean point on the tree / local diameter): %.3f\n",
              t.jitter_n ? std::sqrt(t.jitter_sq / t.jitter_n) : 0.0);
  std::printf("frames to lock after the first feasible view: median %d, max %d, within 5 frames %d of %zu "
              "(never locked %d)\n",
              locked.empty() ? -1 : locked[locked.size() / 2], locked.empty() ? -1 : locked.back(), within5,
              t.locks.size(), never);
  std::printf("tracker time: %.4f ms per frame (beyond find_perch)\n",
              t.frames ? t.tracker_ms / t.frames : 0.0);
  if (t.errors) std::printf("errors: %d sequences\n", t.errors);
}

std::string json_of(const totals& t, int frames_per_sequence, std::string_view motion) {
  st::json_writer json;
  std::vector<int> locked;
  for (const int l : t.locks)
    if (l >= 0) locked.push_back(l);
  std::sort(locked.begin(), locked.end());
  json.begin_object()
      .key("sequences").value(static_cast<std::int64_t>(t.sequences))
      .key("frames_per_sequence").value(static_cast<std::int64_t>(frames_per_sequence))
      .key("motion").value(motion)
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
      .end_object();
  return std::move(json).take();
}

}  // namespace

int run_track_eval(int argc, const char* const* argv) {
  st::arg_parser args(
      "perch eval --sequences",
      "Runs find_perch and the tracker on N synthetic approach sequences (one tree of the arcs\n"
      "population each, filmed approaching from 3x to 1x the distance with drift, roll, shake and\n"
      "segmentation noise) and scores the target against each frame's truth.");
  args.add_option("sequences", "N", "number of sequences", "40");
  args.add_option("frames", "F", "frames per sequence", "90");
  args.add_option("motion", "SOURCE", "the tracker's camera motion: truth (as visual odometry would\n"
                                      "give it), estimated (from the masks: motion_estimator) or none (identity)", "truth");
  args.add_option("jobs", "N", "worker threads; 0 = all cores", "0", 'j');
  args.add_option("json", "OUT.json", "also write the totals as JSON");
  args.add_flag("rows", "one row per sequence");
  args.add_flag("quiet", "no progress bar");
  args.set_epilog(
      "find_perch gets each frame's true scale (fixed_scale) and roll (perch_options::camera).\n"
      "On a feasible stretch: within 3 px + 3 % of the window of a feasible window centre of the\n"
      "frame's truth. A switch away from a target is unwarranted when the old target, moved with\n"
      "the camera, is still in view and on a feasible stretch. Jitter: per run of one target id,\n"
      "the RMS distance of the target from the run's mean point (in the tree's own pixels) over\n"
      "the local truth diameter. Lock: frames from the first frame with a feasible stretch to the\n"
      "first frame whose target is on one.\n"
      "Example: perch eval --sequences 40 --frames 90 --rows");
  int exit = exit_ok;
  if (!parse_or_exit(args, argc, argv, "eval", exit)) return exit;
  const auto n = args.get_int("sequences", 40, 1, 100000);
  const auto frames = args.get_int("frames", 90, 2, 100000);
  const auto jobs = args.get_int("jobs", 0, 0, 1024);
  for (const auto* v : {&n, &frames, &jobs})
    if (!*v) {
      report_error("eval", v->error);
      return exit_usage;
    }
  const std::string motion = args.get_string("motion", "truth").value;
  if (motion != "truth" && motion != "none" && motion != "estimated") {
    report_error("eval", "--motion must be truth, estimated or none, not " + motion);
    return exit_usage;
  }
  const motion_source source = motion == "truth"       ? motion_source::truth
                               : motion == "estimated" ? motion_source::estimated
                                                       : motion_source::none;
  st::sequence_options options;
  options.frames = frames.value;
  const auto count = static_cast<std::size_t>(n.value);
  const unsigned workers = st::worker_count(count, static_cast<unsigned>(jobs.value));
  std::vector<std::unique_ptr<workspace>> spaces;
  for (unsigned w = 0; w < workers; ++w) spaces.push_back(std::make_unique<workspace>());
  st::progress_options progress_options;
  if (args.flag("quiet")) progress_options.display = st::progress_display::off;
  st::progress_bar progress(count, progress_options);
  const std::vector<sequence_score> scores =
      st::parallel_map(count, static_cast<unsigned>(jobs.value), [&](std::size_t i, unsigned worker) {
        sequence_score s = score_sequence(static_cast<int>(i), options, source, *spaces[worker]);
        progress.tick();
        return s;
      });
  progress.finish();
  const totals t = add_up(scores);
  std::printf("perch eval --sequences: %d sequences of %d frames, motion %s\n\n", n.value, frames.value,
              motion.c_str());
  print_scores(scores, t, args.flag("rows"));
  if (args.has("json")) {
    if (const std::string e = write_text(std::string(*args.value("json")), json_of(t, frames.value, motion));
        !e.empty()) {
      report_error("eval", e);
      return exit_internal;
    }
  }
  return t.errors > 0 ? exit_internal : exit_ok;
}

}  // namespace perch::tool
