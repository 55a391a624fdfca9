// SPDX-License-Identifier: BSL-1.0
// The tracker's cost per frame beyond find_perch (issue 27 asks <= 0.5 ms at 1920x1080, no
// allocation): perch_tracker::update with a given motion, and motion_estimator::update (the
// motion from the masks' skeleton junctions and ends), on two frames of a 1920x1080 approach
// analysed once beforehand, alternated so that every update has a real step to follow; and
// the same with the frames' depth and the camera (the tracks' metric positions).
#include <benchmark/benchmark.h>

#include <array>
#include <cstdint>
#include <memory>
#include <optional>

#include "perch/pli.hpp"
#include "perch/track.hpp"
#include "support/sequence.hpp"

namespace {

namespace st = perch::support;

/// Two consecutive frames of a 1920x1080 approach, analysed, each in its own workspace (with
/// `depth`: scaled by the frames' depth images, so the sites carry metric positions).
struct analysed_pair {
  std::array<perch::image<std::uint16_t>, 2> depth{};
  perch::pinhole camera{};
  std::array<std::unique_ptr<perch::workspace>, 2> ws{std::make_unique<perch::workspace>(),
                                                      std::make_unique<perch::workspace>()};
  std::array<perch::result<perch::perch_result>, 2> found{perch::fail(perch::errc::empty_image),
                                                          perch::fail(perch::errc::empty_image)};
  perch::camera_motion forward{}, backward{};

  explicit analysed_pair(bool with_depth) {
    st::tree_options o = st::benchmark_tree_options(1920, 1080, st::tree_noise::noisy);
    const st::synthetic_tree world = st::make_tree(o);
    st::sequence_options so;
    so.frames = 30;
    const st::approach_sequence seq(world, so);
    for (int k = 0; k < 2; ++k) {
      const st::sequence_frame f = seq.frame(20 + k);
      const auto i = static_cast<std::size_t>(k);
      camera = seq.camera();
      depth[i] = seq.depth_mm(f);
      found[i] = with_depth ? perch::find_perch(f.mask.view(), perch::tendon_claw{},
                                                perch::depth_scale{depth[i].view(), camera}, *ws[i])
                            : perch::find_perch(f.mask.view(), perch::tendon_claw{},
                                                perch::fixed_scale{f.tree.mm_per_px}, *ws[i]);
      if (k == 1) forward = f.motion;
    }
    backward = st::detail::sequences::inverse_similarity(forward);
  }
};

const analysed_pair& pair(bool with_depth = false) {
  static const analysed_pair plain(false);
  static const analysed_pair metric(true);
  return with_depth ? metric : plain;
}

/// `state.range(0)`: 1 with depth and the camera.
void tracker_update_1080p(benchmark::State& state) {
  const bool with_depth = state.range(0) != 0;
  const analysed_pair& p = pair(with_depth);
  if (!p.found[0] || !p.found[1]) {
    state.SkipWithError("find_perch failed");
    return;
  }
  perch::perch_tracker tracker({}, with_depth ? std::optional<perch::pinhole>(p.camera) : std::nullopt);
  std::size_t k = 0;
  for (auto _ : state) {
    const perch::tracking_result r = tracker.update(*p.found[k], k == 0 ? p.backward : p.forward);
    benchmark::DoNotOptimize(r.target);
    k ^= 1u;
  }
  state.counters["tracks"] = static_cast<double>(tracker.tracks().size());
  state.counters["sites"] = static_cast<double>(p.found[0]->sites.size());
  state.counters["metric"] =
      tracker.tracks().empty() ? 0.0 : static_cast<double>(tracker.tracks()[0].has_position);
}
BENCHMARK(tracker_update_1080p)->ArgName("depth")->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void motion_estimate_1080p(benchmark::State& state) {
  const analysed_pair& p = pair();
  if (!p.found[0] || !p.found[1]) {
    state.SkipWithError("find_perch failed");
    return;
  }
  perch::motion_estimator estimator;
  std::size_t k = 0, estimated = 0, frames = 0;
  for (auto _ : state) {
    const perch::motion_estimate m = estimator.update(*p.found[k]);
    benchmark::DoNotOptimize(m.motion);
    estimated += m.estimated ? 1u : 0u;
    ++frames;
    k ^= 1u;
  }
  state.counters["estimated_share"] = frames ? static_cast<double>(estimated) / static_cast<double>(frames) : 0;
  state.counters["keypoints"] = static_cast<double>(estimator.update(*p.found[0]).keypoints);
}
BENCHMARK(motion_estimate_1080p)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
