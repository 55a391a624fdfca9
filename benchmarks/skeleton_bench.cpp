// SPDX-License-Identifier: BSL-1.0
// Skeleton stage: medial axis, Zhang-Suen and Guo-Hall (default one-pixel mode, and faithful
// for the thinning methods) on synthetic tree masks at 640x480, 1920x1080 and 4000x3000 and a
// 50 % blob mask; with OpenCV's ximgproc, cv::ximgproc::thinning on the same masks, reporting
// how many pixels differ from perch's faithful output of the same method.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "perch/core/huge_pages.hpp"
#include "perch/core/image.hpp"
#include "kernel_masks.hpp"
#include "perch/distance.hpp"
#include "perch/skeleton.hpp"

#if PERCH_HAVE_OPENCV && __has_include(<opencv2/ximgproc.hpp>)
#include <opencv2/ximgproc.hpp>
#define PERCH_BENCH_XIMGPROC 1
#endif

namespace {

using perch::bench::blob_mask;
using perch::bench::foreground_share;
using perch::bench::tree_mask;

/// `HugePages`: the workspace in transparent huge pages (`perch::huge_page_resource`).
template <class S, bool Blob, bool HugePages = false>
void perch_skeleton(benchmark::State& state, S method) {
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const auto mask = Blob ? blob_mask(w, h) : tree_mask(w, h);
  perch::image<std::uint32_t> d2(w, h);
  perch::image<std::uint8_t> out(w, h);
  perch::huge_page_resource huge_pages;
  perch::workspace ws{HugePages ? static_cast<std::pmr::memory_resource*>(&huge_pages)
                                : std::pmr::new_delete_resource()};
  if (!perch::distance_transform_sq(mask.view(), d2.view(), ws)) state.SkipWithError("edt");
  if (!method(mask.view(), d2.view(), out.view(), ws)) state.SkipWithError("skeleton");
  for (auto _ : state) {
    auto s = method(mask.view(), d2.view(), out.view(), ws);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(out.data());
  }
  std::size_t count = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) count += out(x, y);
  state.counters["skeleton_px"] = static_cast<double>(count);
  state.counters["fg_%"] = 100.0 * foreground_share(mask);
  state.counters["pixels/s"] = benchmark::Counter(static_cast<double>(w) * h,
                                                  benchmark::Counter::kIsIterationInvariantRate);
}

using perch::thinness;
void medial_tree(benchmark::State& s) { perch_skeleton<perch::medial_axis, false>(s, {}); }
void medial_blob(benchmark::State& s) { perch_skeleton<perch::medial_axis, true>(s, {}); }
void medial_tree_huge_pages(benchmark::State& s) {
  perch_skeleton<perch::medial_axis, false, true>(s, {});
}
void zhang_tree(benchmark::State& s) { perch_skeleton<perch::zhang_suen, false>(s, {}); }
void zhang_faithful(benchmark::State& s) {
  perch_skeleton<perch::zhang_suen, false>(s, {.thinness = thinness::faithful});
}
void guo_tree(benchmark::State& s) { perch_skeleton<perch::guo_hall, false>(s, {}); }
void guo_faithful(benchmark::State& s) {
  perch_skeleton<perch::guo_hall, false>(s, {.thinness = thinness::faithful});
}
BENCHMARK(medial_tree)->Name("medial_axis/tree")->Args({640, 480})->Args({1920, 1080})
    ->Args({4000, 3000})->Unit(benchmark::kMillisecond);
BENCHMARK(medial_tree_huge_pages)->Name("medial_axis_huge_pages/tree")->Args({640, 480})
    ->Args({1920, 1080})->Args({4000, 3000})->Unit(benchmark::kMillisecond);
BENCHMARK(medial_blob)->Name("medial_axis/blob50")->Args({1920, 1080})->Unit(benchmark::kMillisecond);
BENCHMARK(zhang_tree)->Name("zhang_suen/tree")->Args({640, 480})->Args({1920, 1080})
    ->Args({4000, 3000})->Unit(benchmark::kMillisecond);
BENCHMARK(zhang_faithful)->Name("zhang_suen_faithful/tree")->Args({1920, 1080})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(guo_tree)->Name("guo_hall/tree")->Args({640, 480})->Args({1920, 1080})
    ->Args({4000, 3000})->Unit(benchmark::kMillisecond);
BENCHMARK(guo_faithful)->Name("guo_hall_faithful/tree")->Args({1920, 1080})
    ->Unit(benchmark::kMillisecond);

#if PERCH_BENCH_XIMGPROC
template <class S>
void opencv_thinning(benchmark::State& state, int type, S faithful) {
  cv::setNumThreads(1);  // one thread, as perch
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  auto mask = tree_mask(w, h);
  perch::image<std::uint8_t> scaled(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) scaled(x, y) = mask(x, y) ? 255 : 0;
  const cv::Mat m(h, w, CV_8U, scaled.data());
  cv::Mat out;
  cv::ximgproc::thinning(m, out, type);
  perch::image<std::uint32_t> d2(w, h);
  perch::image<std::uint8_t> ours(w, h);
  perch::workspace ws;
  if (!perch::distance_transform_sq(mask.view(), d2.view(), ws) ||
      !faithful(mask.view(), d2.view(), ours.view(), ws))
    state.SkipWithError("perch");
  long differ = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) differ += (out.at<std::uint8_t>(y, x) != 0) != (ours(x, y) != 0);
  state.counters["differ_px"] = static_cast<double>(differ);
  for (auto _ : state) {
    cv::ximgproc::thinning(m, out, type);
    benchmark::DoNotOptimize(out.data);
  }
  state.counters["pixels/s"] = benchmark::Counter(static_cast<double>(w) * h,
                                                  benchmark::Counter::kIsIterationInvariantRate);
}
void opencv_zhang(benchmark::State& s) {
  opencv_thinning(s, cv::ximgproc::THINNING_ZHANGSUEN, perch::zhang_suen{.thinness = thinness::faithful});
}
void opencv_guo(benchmark::State& s) {
  opencv_thinning(s, cv::ximgproc::THINNING_GUOHALL, perch::guo_hall{.thinness = thinness::faithful});
}
BENCHMARK(opencv_zhang)->Name("opencv_thinning/zhang_suen/tree")->Args({640, 480})
    ->Args({1920, 1080})->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(opencv_guo)->Name("opencv_thinning/guo_hall/tree")->Args({640, 480})
    ->Args({1920, 1080})->Unit(benchmark::kMillisecond)->Iterations(3);
#endif

}  // namespace

BENCHMARK_MAIN();
