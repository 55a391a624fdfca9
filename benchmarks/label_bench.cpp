// SPDX-License-Identifier: BSL-1.0
// Labelling stage: perch::label_components (8-connectivity, with and without statistics) and
// perch::count_topology on deterministic synthetic masks at 640×480, 1920×1080 and 4000×3000,
// and perch::fill_small_holes (pinholes of up to 4 pixels, `find_perch`'s default) on the same:
//   tree   — a branching tree of thin tapered limbs (about 5–20 % foreground),
//   blob   — overlapping discs, about 50 % foreground,
//   noise  — independent pixels at 50 % (the worst case for any labeller: many tiny components).
// With OpenCV (PERCH_HAVE_OPENCV) the same masks are also labelled by cv::connectedComponents
// (8-connectivity, CV_32S, CCL_SPAGHETTI, one thread), after checking once that both give the
// same partition (labels equal up to a renumbering).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

#include "perch/core/image.hpp"
#include "perch/label.hpp"

#if defined(PERCH_HAVE_OPENCV)
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#endif

namespace {

enum mask_kind : int { tree = 0, blob = 1, noise = 2 };

// Fills the capsule of radius `r` around segment (x0,y0)-(x1,y1).
void draw_limb(perch::image<std::uint8_t>& m, double x0, double y0, double x1, double y1, double r0,
               double r1) {
  const double r = std::max(r0, r1);
  const int xa = std::max(0, static_cast<int>(std::floor(std::min(x0, x1) - r)));
  const int xb = std::min(m.width() - 1, static_cast<int>(std::ceil(std::max(x0, x1) + r)));
  const int ya = std::max(0, static_cast<int>(std::floor(std::min(y0, y1) - r)));
  const int yb = std::min(m.height() - 1, static_cast<int>(std::ceil(std::max(y0, y1) + r)));
  const double dx = x1 - x0;
  const double dy = y1 - y0;
  const double len2 = std::max(1e-9, dx * dx + dy * dy);
  for (int y = ya; y <= yb; ++y)
    for (int x = xa; x <= xb; ++x) {
      const double t = std::clamp(((x - x0) * dx + (y - y0) * dy) / len2, 0.0, 1.0);
      const double px = x0 + t * dx - x;
      const double py = y0 + t * dy - y;
      const double radius = r0 + t * (r1 - r0);
      if (px * px + py * py <= radius * radius) m(x, y) = 1;
    }
}

void grow(perch::image<std::uint8_t>& m, std::mt19937& rng, double x, double y, double angle,
          double length, double radius, int depth) {
  std::uniform_real_distribution<double> jitter(-0.35, 0.35);
  std::uniform_real_distribution<double> shrink(0.62, 0.8);
  // A limb in a few slightly bent pieces.
  const int pieces = 4;
  double r = radius;
  for (int i = 0; i < pieces; ++i) {
    const double a = angle + jitter(rng) * 0.4;
    const double nx = x + std::cos(a) * length / pieces;
    const double ny = y - std::sin(a) * length / pieces;
    const double nr = std::max(0.5, r * 0.93);
    draw_limb(m, x, y, nx, ny, r, nr);
    x = nx;
    y = ny;
    r = nr;
  }
  if (depth == 0) return;
  const int children = 2 + static_cast<int>(rng() % 2);
  for (int c = 0; c < children; ++c) {
    const double spread = (c - (children - 1) / 2.0) * 0.55 + jitter(rng);
    grow(m, rng, x, y, angle + spread, length * shrink(rng), std::max(0.5, r * 0.75), depth - 1);
  }
}

perch::image<std::uint8_t> make_mask(int width, int height, mask_kind kind) {
  perch::image<std::uint8_t> m(width, height, 0);
  std::mt19937 rng(static_cast<std::uint32_t>(width * 7 + height * 13 + kind));
  const double scale = std::min(width, height);
  if (kind == tree) {
    grow(m, rng, width / 2.0, height - 1.0, M_PI / 2, scale * 0.32, scale * 0.02, 7);
  } else if (kind == blob) {
    const double r = scale * 0.03;
    const int discs = static_cast<int>(std::log(2.0) * width * height / (M_PI * r * r));
    std::uniform_real_distribution<double> xs(0, width);
    std::uniform_real_distribution<double> ys(0, height);
    std::uniform_real_distribution<double> rs(0.3 * r, 1.7 * r);
    for (int i = 0; i < discs; ++i) {
      const double x = xs(rng);
      const double y = ys(rng);
      draw_limb(m, x, y, x, y, rs(rng), 0.0);
    }
  } else {
    for (int y = 0; y < height; ++y)
      for (auto& p : m.row(y)) p = static_cast<std::uint8_t>(rng() & 1u);
  }
  return m;
}

double foreground_fraction(const perch::image<std::uint8_t>& m) {
  std::size_t n = 0;
  for (int y = 0; y < m.height(); ++y)
    for (const auto p : m.row(y)) n += p != 0;
  return static_cast<double>(n) / static_cast<double>(m.width() * m.height());
}

const perch::image<std::uint8_t>& cached_mask(int width, int height, mask_kind kind) {
  static std::map<std::tuple<int, int, int>, perch::image<std::uint8_t>> cache;
  auto key = std::make_tuple(width, height, static_cast<int>(kind));
  auto it = cache.find(key);
  if (it == cache.end()) it = cache.emplace(key, make_mask(width, height, kind)).first;
  return it->second;
}

void set_counters(benchmark::State& state, const perch::image<std::uint8_t>& mask,
                  std::int32_t components) {
  state.counters["pixels/s"] = benchmark::Counter(static_cast<double>(mask.width()) * mask.height(),
                                                  benchmark::Counter::kIsIterationInvariantRate);
  state.counters["fg_%"] = 100.0 * foreground_fraction(mask);
  state.counters["components"] = components;
}

void perch_label(benchmark::State& state) {
  const auto& mask = cached_mask(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                                 static_cast<mask_kind>(state.range(2)));
  perch::image<std::int32_t> labels(mask.width(), mask.height());
  perch::workspace ws;
  if (!ws.reserve(perch::label_workspace_bytes(mask.width(), mask.height()))) {
    state.SkipWithError("workspace");
    return;
  }
  std::int32_t n = 0;
  for (auto _ : state) {
    auto r = perch::label_components(mask.view(), labels.view(), ws, perch::connectivity::eight);
    n = r.value_or(-1);
    benchmark::DoNotOptimize(labels.data());
    benchmark::ClobberMemory();
  }
  set_counters(state, mask, n);
}

void perch_label_stats(benchmark::State& state) {
  const auto& mask = cached_mask(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                                 static_cast<mask_kind>(state.range(2)));
  perch::image<std::int32_t> labels(mask.width(), mask.height());
  perch::workspace ws;
  std::vector<perch::component_stats> storage(mask.view().size() / 4 + 1);
  std::int32_t n = 0;
  for (auto _ : state) {
    perch::bounded_vector<perch::component_stats> stats(storage);
    auto r = perch::label_components(mask.view(), labels.view(), stats, ws);
    n = r.value_or(-1);
    benchmark::DoNotOptimize(stats.begin());
    benchmark::ClobberMemory();
  }
  set_counters(state, mask, n);
}

void perch_topology(benchmark::State& state) {
  const auto& mask = cached_mask(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                                 static_cast<mask_kind>(state.range(2)));
  perch::workspace ws;
  std::int32_t n = 0;
  for (auto _ : state) {
    auto r = perch::count_topology(mask.view(), ws);
    n = r ? r->components : -1;
    benchmark::DoNotOptimize(r);
  }
  set_counters(state, mask, n);
}

// Only the fill is timed (manual time): each iteration starts from a fresh copy of the mask
// and its runs, listed outside the timed part.
void perch_fill_small_holes(benchmark::State& state) {
  const auto& mask = cached_mask(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                                 static_cast<mask_kind>(state.range(2)));
  perch::image<std::uint8_t> copy(mask.width(), mask.height());
  perch::workspace ws;
  const std::size_t max_runs = mask.view().size() / 2 + static_cast<std::size_t>(mask.height());
  std::int32_t filled = 0;
  std::size_t run_count = 0;
  for (auto _ : state) {
    std::copy(mask.data(), mask.data() + mask.view().size(), copy.data());
    ws.reset();
    auto runs =
        perch::find_row_runs(perch::image_view<const std::uint8_t>(copy.view()), ws, max_runs);
    if (!runs) {
      state.SkipWithError("runs");
      return;
    }
    run_count = runs->size();
    const auto start = std::chrono::steady_clock::now();
    auto r = perch::fill_small_holes(copy.view(), *runs, 4, ws);
    const auto stop = std::chrono::steady_clock::now();
    filled = r ? r->filled : -1;
    benchmark::DoNotOptimize(copy.data());
    state.SetIterationTime(std::chrono::duration<double>(stop - start).count());
  }
  set_counters(state, mask, 0);
  state.counters.erase("components");
  state.counters["holes_filled"] = filled;
  state.counters["runs"] = static_cast<double>(run_count);
}

#if defined(PERCH_HAVE_OPENCV)
// True when the two label images describe the same partition (a bijection between labels).
bool same_partition(const perch::image<std::int32_t>& a, const cv::Mat& b) {
  std::map<std::int32_t, std::int32_t> forward;
  std::map<std::int32_t, std::int32_t> backward;
  for (int y = 0; y < a.height(); ++y)
    for (int x = 0; x < a.width(); ++x) {
      const std::int32_t la = a(x, y);
      const std::int32_t lb = b.at<std::int32_t>(y, x);
      if ((la == 0) != (lb == 0)) return false;
      if (la == 0) continue;
      auto [f, f_new] = forward.emplace(la, lb);
      auto [g, g_new] = backward.emplace(lb, la);
      if (f->second != lb || g->second != la) return false;
    }
  return true;
}

void opencv_spaghetti(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& mask = cached_mask(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                                 static_cast<mask_kind>(state.range(2)));
  const cv::Mat in(mask.height(), mask.width(), CV_8UC1, const_cast<std::uint8_t*>(mask.data()));
  cv::Mat labels;
  {
    perch::image<std::int32_t> ours(mask.width(), mask.height());
    perch::workspace ws;
    const auto n = perch::label_components(mask.view(), ours.view(), ws);
    const int m = cv::connectedComponents(in, labels, 8, CV_32S, cv::CCL_SPAGHETTI);
    if (!n || *n != m - 1 || !same_partition(ours, labels)) {
      state.SkipWithError("OpenCV and perch labels disagree");
      return;
    }
  }
  int n = 0;
  for (auto _ : state) {
    n = cv::connectedComponents(in, labels, 8, CV_32S, cv::CCL_SPAGHETTI);
    benchmark::DoNotOptimize(labels.data);
    benchmark::ClobberMemory();
  }
  set_counters(state, mask, n - 1);
}
#endif

void sizes(benchmark::internal::Benchmark* b) {
  for (int kind : {tree, blob, noise})
    for (auto [w, h] : {std::pair{640, 480}, std::pair{1920, 1080}, std::pair{4000, 3000}})
      b->Args({w, h, kind});
  b->ArgNames({"w", "h", "kind"})->Unit(benchmark::kMillisecond);
}

BENCHMARK(perch_label)->Apply(sizes);
#if defined(PERCH_HAVE_OPENCV)
BENCHMARK(opencv_spaghetti)->Apply(sizes);
#endif
BENCHMARK(perch_label_stats)->Apply(sizes);
BENCHMARK(perch_topology)->Apply(sizes);
BENCHMARK(perch_fill_small_holes)->Apply(sizes)->UseManualTime();

}  // namespace

BENCHMARK_MAIN();
