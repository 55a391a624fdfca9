// SPDX-License-Identifier: BSL-1.0
// One side of `scripts/ab.sh`: the library of one revision, compiled with its namespace renamed
// (-Dperch=perch_a or perch_b) so that two revisions live in one binary, and its entry points
// named by AB_RUN and AB_HASH.
#include <chrono>
#include <cstdint>

#include "perch/pli.hpp"
#include "support/synthetic_tree.hpp"

namespace {

std::int64_t now_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// FNV-1a over bytes.
struct fnv {
  std::uint64_t h = 1469598103934665603ull;
  void add(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 1099511628211ull;
  }
};

}  // namespace

// One `find_perch` call (tendon claw, known scale) on the benchmark tree of `w` × `h`, made and
// given a workspace on the first call; its stage times (total, prepare, distance, skeleton,
// graph, prune, windows, ranking; ms) in `out`.
void AB_RUN(int w, int h, bool noisy, float* out) {
  using namespace perch;
  static support::synthetic_tree* tree = nullptr;
  static workspace* ws = nullptr;
  if (tree == nullptr) {
    tree = new support::synthetic_tree(support::benchmark_tree(
        w, h, noisy ? support::tree_noise::noisy : support::tree_noise::clean));
    ws = new workspace;
  }
  perch_options options;
  options.clock = now_ns;
  const auto found =
      find_perch(tree->mask.view(), tendon_claw{}, fixed_scale{tree->mm_per_px}, *ws, options);
  const stage_timings t = found ? found->timing : stage_timings{};
  const float v[8] = {t.total_ms, t.prepare_ms, t.distance_ms, t.skeleton_ms,
                      t.graph_ms, t.prune_ms,   t.windows_ms,  t.ranking_ms};
  for (int k = 0; k < 8; ++k) out[k] = v[k];
}

// What a change must leave alone: over 44 synthetic trees (clean and noisy, 437 × 329 to
// 1214 × 938), the skeleton, `dist2` on tree pixels, each site's centre, smallest diameter and
// penalty, and the window counts.
std::uint64_t AB_HASH() {
  using namespace perch;
  fnv f;
  workspace ws;
  for (int s = 1; s <= 22; ++s)
    for (int noisy = 0; noisy < 2; ++noisy) {
      support::tree_options o;
      o.width = 400 + 37 * s;
      o.height = 300 + 29 * s;
      o.seed = static_cast<std::uint32_t>(s);
      o.mm_per_px = 2.0f;
      if (noisy != 0) {
        o.noise = 3;
        o.twigs = 10;
        o.holes = 2;
        o.crossings = 1;
      }
      const auto t = support::make_tree(o);
      const auto r = find_perch(t.mask.view(), tendon_claw{}, fixed_scale{t.mm_per_px}, ws, {});
      if (!r) {
        f.add("err", 3);
        continue;
      }
      for (int y = 0; y < r->skeleton.height(); ++y)
        for (int x = 0; x < r->skeleton.width(); ++x) {
          const std::uint8_t on = r->skeleton(x, y) != 0;
          f.add(&on, 1);
          if (r->mask.pixels(x, y) != 0) {
            const std::uint32_t d = r->dist2(x, y);
            f.add(&d, 4);
          }
        }
      for (const auto& site : r->sites) {
        const float v[3] = {static_cast<float>(site.window.centre.x),
                            static_cast<float>(site.window.centre.y), site.window.diameter_min_mm};
        f.add(v, sizeof v);
        f.add(&site.penalty, sizeof site.penalty);
      }
      f.add(&r->windows, sizeof r->windows);
      f.add(&r->viable, sizeof r->viable);
    }
  return f.h;
}
