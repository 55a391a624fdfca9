// SPDX-License-Identifier: BSL-1.0
// find_perch end to end (issue 8): every platform on the synthetic benchmark trees at 640×480,
// 1920×1080 and 4000×3000, clean and noisy, one thread, the workspace made once outside the
// loop (for the tendon claw also in transparent huge pages). Counters: per-stage milliseconds
// (medians are taken by --benchmark_repetitions), pixels/s, workspace bytes per pixel and heap
// allocations per iteration (must be 0); and the first call on a workspace whose memory comes
// fresh from the kernel, against the warm call (issue 25: at most 3×). With OpenCV, the same
// trees through its distance transform and thinning, for the README's table.
#include <benchmark/benchmark.h>

#include <sys/mman.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory_resource>
#include <new>
#include <string>
#include <utility>

#include "perch/core/huge_pages.hpp"
#include "perch/pli.hpp"
#include "support/synthetic_tree.hpp"

#if PERCH_HAVE_OPENCV
#include <opencv2/imgproc.hpp>

#include "opencv_check.hpp"
#if __has_include(<opencv2/ximgproc.hpp>)
#include <opencv2/ximgproc.hpp>
#define PERCH_BENCH_XIMGPROC 1
#endif
#endif

namespace {

std::atomic<long long> g_allocations{0};

std::int64_t steady_ns() noexcept {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

using perch::support::tree_noise;

/// The benchmark trees, generated once per size and noise.
const perch::support::synthetic_tree& tree_for(int width, int height, tree_noise noise) {
  static std::map<std::pair<int, int>, perch::support::synthetic_tree> clean, noisy;
  auto& cache = noise == tree_noise::noisy ? noisy : clean;
  auto it = cache.find({width, height});
  if (it == cache.end())
    it = cache.emplace(std::pair{width, height}, perch::support::benchmark_tree(width, height, noise)).first;
  return it->second;
}

/// The tree of a benchmark's arguments: width, height, noisy (0/1).
const perch::support::synthetic_tree& tree_of(const benchmark::State& state) {
  return tree_for(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)),
                  state.range(2) != 0 ? tree_noise::noisy : tree_noise::clean);
}

/// `HugePages`: the timed workspace's block comes from `perch::huge_page_resource`.
template <class Platform, bool HugePages = false>
void find_perch_on_tree(benchmark::State& state) {
  const auto& tree = tree_of(state);
  const int width = tree.mask.width();
  const int height = tree.mask.height();
  const perch::fixed_scale scale{tree.mm_per_px};
  perch::perch_options options;
  options.clock = steady_ns;
  perch::workspace grown;
  auto warm = perch::find_perch(tree.mask.view(), Platform{}, scale, grown, options);
  if (!warm) {
    state.SkipWithError(std::string(warm.error().message()).c_str());
    return;
  }
  // The timed calls use one block of the warm call's size, as firmware sizes its buffer: a
  // workspace that grew block by block also counts the block tails it skipped.
  perch::huge_page_resource huge_pages;
  perch::workspace ws{HugePages ? static_cast<std::pmr::memory_resource*>(&huge_pages)
                                : std::pmr::new_delete_resource()};
  if (!ws.reserve(grown.high_water())) {
    state.SkipWithError("reserve");
    return;
  }
  // One call on it outside the timing, as a robot's first frame: the block's pages are touched
  // (faulted in and zeroed by the kernel) here, not in the first timed call.
  if (!perch::find_perch(tree.mask.view(), Platform{}, scale, ws, options)) {
    state.SkipWithError("find_perch on the reserved workspace");
    return;
  }
  perch::stage_timings sum{};
  long long allocations = 0;  // inside find_perch only: the framework's own loop allocates
  std::size_t sites = 0;
  for (auto _ : state) {
    const long long before = g_allocations.load(std::memory_order_relaxed);
    auto found = perch::find_perch(tree.mask.view(), Platform{}, scale, ws, options);
    allocations += g_allocations.load(std::memory_order_relaxed) - before;
    benchmark::DoNotOptimize(found);
    const perch::stage_timings& t = found->timing;
    sum.prepare_ms += t.prepare_ms;
    sum.distance_ms += t.distance_ms;
    sum.skeleton_ms += t.skeleton_ms;
    sum.graph_ms += t.graph_ms;
    sum.prune_ms += t.prune_ms;
    sum.windows_ms += t.windows_ms;
    sum.ranking_ms += t.ranking_ms;
    sites = found->sites.size();
  }
  const auto n = static_cast<double>(state.iterations());
  auto avg = [&](float ms) { return benchmark::Counter(static_cast<double>(ms) / n); };
  state.counters["prepare_ms"] = avg(sum.prepare_ms);
  state.counters["distance_ms"] = avg(sum.distance_ms);
  state.counters["skeleton_ms"] = avg(sum.skeleton_ms);
  state.counters["graph_ms"] = avg(sum.graph_ms);
  state.counters["prune_ms"] = avg(sum.prune_ms);
  state.counters["windows_ms"] = avg(sum.windows_ms);
  state.counters["ranking_ms"] = avg(sum.ranking_ms);
  state.counters["allocs/iter"] =
      benchmark::Counter(static_cast<double>(allocations) / n);
  state.counters["ws_bytes/px"] = benchmark::Counter(
      static_cast<double>(ws.high_water()) / (static_cast<double>(width) * height));
  state.counters["sites"] = benchmark::Counter(static_cast<double>(sites));
  state.counters["pixels/s"] = benchmark::Counter(static_cast<double>(width) * height,
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

// Arguments: width, height, noisy (0/1).
#define PERCH_SIZES                                                                     \
  ->Args({640, 480, 0})->Args({640, 480, 1})->Args({1920, 1080, 0})->Args({1920, 1080, 1}) \
      ->Args({4000, 3000, 0})->Args({4000, 3000, 1})->Unit(benchmark::kMillisecond)

BENCHMARK(find_perch_on_tree<perch::tendon_claw>) PERCH_SIZES;
BENCHMARK(find_perch_on_tree<perch::tensile_tether>) PERCH_SIZES;
BENCHMARK(find_perch_on_tree<perch::metamorphic_quadrotor>) PERCH_SIZES;
BENCHMARK(find_perch_on_tree<perch::ornithopter>) PERCH_SIZES;
BENCHMARK(find_perch_on_tree<perch::treecreeper>) PERCH_SIZES;

/// The tendon claw with its workspace in transparent huge pages (Linux; see huge_pages.hpp).
void find_perch_in_huge_pages(benchmark::State& state) {
  find_perch_on_tree<perch::tendon_claw, true>(state);
}
BENCHMARK(find_perch_in_huge_pages)
    ->Args({640, 480, 0})->Args({1920, 1080, 0})->Args({4000, 3000, 0})
    ->Unit(benchmark::kMillisecond);

/// Pages straight from the kernel and back (mmap / munmap), as a process's first frame gets its
/// heap blocks, hinted for transparent huge pages as the default workspace hints its own: every
/// call on a workspace over it faults its memory in afresh.
class fresh_pages final : public std::pmr::memory_resource {
  void* do_allocate(std::size_t bytes, std::size_t) override {
    void* p = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (p == MAP_FAILED) return nullptr;
    perch::detail::hint_huge_pages(p, bytes);
    return p;
  }
  void do_deallocate(void* p, std::size_t bytes, std::size_t) override { ::munmap(p, bytes); }
  bool do_is_equal(const std::pmr::memory_resource& other) const noexcept override {
    return this == &other;
  }
};

/// A robot's first frame, or a tool's only call: `find_perch` on a new workspace whose memory
/// comes fresh from the kernel (the workspace grows block by block, each page faulted in and
/// zeroed). Counters: the warm call on a grown workspace (best of 5) and first / warm.
void find_perch_first_call(benchmark::State& state) {
  const auto& tree = tree_of(state);
  const perch::fixed_scale scale{tree.mm_per_px};
  perch::workspace grown;
  double warm_ms = 1e30;
  for (int i = 0; i < 6; ++i) {
    const std::int64_t t0 = steady_ns();
    auto found = perch::find_perch(tree.mask.view(), perch::tendon_claw{}, scale, grown);
    const std::int64_t t1 = steady_ns();
    if (!found) {
      state.SkipWithError(std::string(found.error().message()).c_str());
      return;
    }
    if (i > 0) warm_ms = std::min(warm_ms, static_cast<double>(t1 - t0) / 1e6);
  }
  double first_ms = 0;
  for (auto _ : state) {
    fresh_pages pages;
    perch::workspace ws{&pages};
    const std::int64_t t0 = steady_ns();
    auto found = perch::find_perch(tree.mask.view(), perch::tendon_claw{}, scale, ws);
    const std::int64_t t1 = steady_ns();
    benchmark::DoNotOptimize(found);
    state.SetIterationTime(static_cast<double>(t1 - t0) / 1e9);
    first_ms += static_cast<double>(t1 - t0) / 1e6;
  }
  const double mean_ms = first_ms / static_cast<double>(state.iterations());
  state.counters["warm_ms"] = benchmark::Counter(warm_ms);
  state.counters["first/warm"] = benchmark::Counter(mean_ms / warm_ms);
}
BENCHMARK(find_perch_first_call)
    ->Args({640, 480, 0})->Args({1920, 1080, 0})->Args({4000, 3000, 0})
    ->UseManualTime()->Unit(benchmark::kMillisecond);

#if PERCH_HAVE_OPENCV
/// The same trees through OpenCV's nearest kernels, one thread, for the table next to the
/// stages: the distance stage's (`cv::distanceTransform`, L2 precise, on the whole frame, after
/// checking that it gives perch's distances: `differ_px`).
void opencv_distance_on_tree(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& tree = tree_of(state);
  const int width = tree.mask.width();
  const int height = tree.mask.height();
  state.counters["differ_px"] = static_cast<double>(perch::bench::opencv_edt_differ_px(tree.mask));
  const cv::Mat m(height, width, CV_8U, const_cast<std::uint8_t*>(tree.mask.data()));
  cv::Mat dist;
  for (auto _ : state) {
    cv::distanceTransform(m, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
    benchmark::DoNotOptimize(dist.data);
  }
}
BENCHMARK(opencv_distance_on_tree) PERCH_SIZES;

#if PERCH_BENCH_XIMGPROC
/// And the skeleton stage's nearest: `cv::ximgproc::thinning` (Zhang–Suen; a thinning, not a
/// medial axis: skeleton_bench compares it with perch's). At 4000×3000 one call takes seconds,
/// so the two smaller sizes only.
void opencv_thinning_on_tree(benchmark::State& state) {
  cv::setNumThreads(1);
  const auto& tree = tree_of(state);
  const int width = tree.mask.width();
  const int height = tree.mask.height();
  cv::Mat m(height, width, CV_8U);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) m.at<std::uint8_t>(y, x) = tree.mask(x, y) != 0 ? 255 : 0;
  cv::Mat out;
  for (auto _ : state) {
    cv::ximgproc::thinning(m, out, cv::ximgproc::THINNING_ZHANGSUEN);
    benchmark::DoNotOptimize(out.data);
  }
}
BENCHMARK(opencv_thinning_on_tree)
    ->Args({640, 480, 0})
    ->Args({640, 480, 1})
    ->Args({1920, 1080, 0})
    ->Args({1920, 1080, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);
#endif
#endif

/// The downscale option: the same 4000×3000 tree analysed at factors 1, 0.5 and 0.25.
void find_perch_downscaled(benchmark::State& state) {
  const auto& tree = tree_for(4000, 3000, tree_noise::clean);
  perch::perch_options options;
  options.downscale = static_cast<float>(state.range(0)) / 100.0f;
  perch::workspace ws;
  const perch::fixed_scale scale{tree.mm_per_px};
  // Warm-up outside the timing: the first call sizes the workspace (and faults its pages in).
  if (!perch::find_perch(tree.mask.view(), perch::tendon_claw{}, scale, ws, options)) {
    state.SkipWithError("find_perch failed");
    return;
  }
  for (auto _ : state) {
    auto found = perch::find_perch(tree.mask.view(), perch::tendon_claw{}, scale, ws, options);
    benchmark::DoNotOptimize(found);
  }
  state.counters["pixels/s"] = benchmark::Counter(4000.0 * 3000.0,
                                                  benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(find_perch_downscaled)->Arg(100)->Arg(50)->Arg(25)->Unit(benchmark::kMillisecond);

}  // namespace

// Counts every heap allocation in the process; `allocs/iter` reads it around each find_perch call.
// The replacements pair malloc with free on purpose.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void* operator new(std::size_t size) {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
// The workspace's blocks: aligned, non-throwing.
void* operator new(std::size_t size, std::align_val_t a, const std::nothrow_t&) noexcept {
  g_allocations.fetch_add(1, std::memory_order_relaxed);
  const auto align = static_cast<std::size_t>(a);
  if (size > static_cast<std::size_t>(-1) - align) return nullptr;
  return std::aligned_alloc(align, (size + align - 1) / align * align);
}
void operator delete(void* p, std::align_val_t, const std::nothrow_t&) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }

BENCHMARK_MAIN();
