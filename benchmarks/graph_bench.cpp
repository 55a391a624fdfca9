// SPDX-License-Identifier: BSL-1.0
// Skeleton graph stage: pixel kinds, junction clusters, branch tracing and the adjacency list
// (build), then eq. 1 weighting and pruning (build + prune), on a synthetic branched skeleton:
// a binary tree of digital segments with short spurs along every branch, as a medial axis of a
// noisy tree mask has. Target (issue 4): under 2 ms at 1920x1080 on one core.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "perch/graph.hpp"

namespace {

struct synthetic_tree {
  int width, height;
  std::vector<std::uint8_t> skeleton;
  std::vector<std::uint32_t> dist2;
  std::size_t pixels = 0;

  synthetic_tree(int w, int h)
      : width(w), height(h), skeleton(static_cast<std::size_t>(w) * static_cast<std::size_t>(h)),
        dist2(skeleton.size(), 0) {
    const double scale = static_cast<double>(h) / 1080.0;
    grow(w / 2, h - 1, -M_PI / 2, 0.42 * h, 18.0 * scale, 0);
    for (const std::uint8_t p : skeleton) pixels += p;
  }

  void put(int x, int y, double r) {
    if (x < 0 || y < 0 || x >= width || y >= height) return;
    const auto i = static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x);
    skeleton[i] = 1;
    const auto d2 = static_cast<std::uint32_t>(std::max(1.0, r * r));
    dist2[i] = std::max(dist2[i], d2);
  }
  void line(int x0, int y0, int x1, int y1, double r) {
    const int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
    const int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1;
    int err = dx + dy;
    for (;;) {
      put(x0, y0, r);
      if (x0 == x1 && y0 == y1) break;
      const int e2 = 2 * err;
      if (e2 >= dy) { err += dy; x0 += sx; }
      if (e2 <= dx) { err += dx; y0 += sy; }
    }
  }
  void grow(int x, int y, double angle, double length, double r, int depth) {
    const int x1 = x + static_cast<int>(std::lround(length * std::cos(angle)));
    const int y1 = y + static_cast<int>(std::lround(length * std::sin(angle)));
    line(x, y, x1, y1, r);
    // Spurs every ~12 px, 3 px long, alternating sides (boundary noise).
    const int steps = static_cast<int>(length / 12.0);
    for (int k = 1; k < steps; ++k) {
      const double t = static_cast<double>(k) / steps;
      const int sx = x + static_cast<int>(std::lround(t * (x1 - x)));
      const int sy = y + static_cast<int>(std::lround(t * (y1 - y)));
      const double side = (k % 2 == 0 ? 1.0 : -1.0) * M_PI / 2;
      line(sx, sy, sx + static_cast<int>(std::lround(3 * std::cos(angle + side))),
           sy + static_cast<int>(std::lround(3 * std::sin(angle + side))), r * 0.5);
    }
    if (depth == 7) return;
    grow(x1, y1, angle - 0.45, length * 0.62, r * 0.7, depth + 1);
    grow(x1, y1, angle + 0.5, length * 0.6, r * 0.7, depth + 1);
  }
  [[nodiscard]] perch::image_view<const std::uint8_t> skeleton_view() const {
    return {skeleton.data(), width, height};
  }
  [[nodiscard]] perch::image_view<const std::uint32_t> dist2_view() const {
    return {dist2.data(), width, height};
  }
};

void graph_build(benchmark::State& state) {
  const synthetic_tree tree(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  perch::workspace ws;
  std::size_t branches = 0;
  for (auto _ : state) {
    ws.reset();
    auto g = perch::build_skeleton_graph(tree.skeleton_view(), tree.dist2_view(), ws);
    if (!g) state.SkipWithError("build failed");
    branches = g->branch_count();
    benchmark::DoNotOptimize(branches);
  }
  state.counters["skeleton_px"] = static_cast<double>(tree.pixels);
  state.counters["branches"] = static_cast<double>(branches);
  state.counters["pixels/s"] = benchmark::Counter(
      static_cast<double>(tree.width) * tree.height, benchmark::Counter::kIsIterationInvariantRate);
}

void graph_build_and_prune(benchmark::State& state) {
  const synthetic_tree tree(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  perch::workspace ws;
  std::size_t before = 0, after = 0;
  for (auto _ : state) {
    ws.reset();
    auto g = perch::build_skeleton_graph(tree.skeleton_view(), tree.dist2_view(), ws);
    if (!g) state.SkipWithError("build failed");
    before = g->branch_count();
    auto report = perch::prune_skeleton_graph(*g, 1.0f, ws);
    if (!report) state.SkipWithError("prune failed");
    after = g->branch_count();
  }
  state.counters["skeleton_px"] = static_cast<double>(tree.pixels);
  state.counters["branches_before"] = static_cast<double>(before);
  state.counters["branches_after"] = static_cast<double>(after);
  state.counters["pixels/s"] = benchmark::Counter(
      static_cast<double>(tree.width) * tree.height, benchmark::Counter::kIsIterationInvariantRate);
}

BENCHMARK(graph_build)->Args({640, 480})->Args({1920, 1080})->Args({4000, 3000})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK(graph_build_and_prune)->Args({640, 480})->Args({1920, 1080})->Args({4000, 3000})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
