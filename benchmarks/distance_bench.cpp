// SPDX-License-Identifier: BSL-1.0
// Distance stage: the exact Euclidean distance transform on synthetic tree masks (thick
// branching strokes, ~10-20 % foreground) and a 50 % blob mask, at 640x480, 1920x1080 and
// 4000x3000; with OpenCV, cv::distanceTransform(DIST_L2, DIST_MASK_PRECISE) on the same masks,
// after checking that both give the same distances.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "perch/core/image.hpp"
#include "kernel_masks.hpp"
#include "perch/distance.hpp"

#if PERCH_HAVE_OPENCV
#include <opencv2/imgproc.hpp>

#include "opencv_check.hpp"
#endif

namespace {

using perch::bench::blob_mask;
using perch::bench::foreground_share;
using perch::bench::tree_mask;

template <bool Blob>
void perch_edt(benchmark::State& state) {
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  const auto mask = Blob ? blob_mask(w, h) : tree_mask(w, h);
  perch::image<std::uint32_t> d2(w, h);
  perch::workspace ws;
  if (!perch::distance_transform_sq(mask.view(), d2.view(), ws)) state.SkipWithError("failed");
  for (auto _ : state) {
    auto s = perch::distance_transform_sq(mask.view(), d2.view(), ws);
    benchmark::DoNotOptimize(s);
    benchmark::DoNotOptimize(d2.data());
  }
  state.counters["pixels/s"] = benchmark::Counter(static_cast<double>(w) * h,
                                                  benchmark::Counter::kIsIterationInvariantRate);
  state.counters["fg_%"] = 100.0 * foreground_share(mask);
}
BENCHMARK(perch_edt<false>)->Name("perch_edt/tree")->Args({640, 480})->Args({1920, 1080})
    ->Args({4000, 3000})->Unit(benchmark::kMillisecond);
BENCHMARK(perch_edt<true>)->Name("perch_edt/blob50")->Args({1920, 1080})
    ->Unit(benchmark::kMillisecond);

#if PERCH_HAVE_OPENCV
template <bool Blob>
void opencv_edt(benchmark::State& state) {
  cv::setNumThreads(1);  // one thread, as perch
  const int w = static_cast<int>(state.range(0)), h = static_cast<int>(state.range(1));
  auto mask = Blob ? blob_mask(w, h) : tree_mask(w, h);
  const cv::Mat m(h, w, CV_8U, mask.data());
  cv::Mat dist;
  cv::distanceTransform(m, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
  const long differ = perch::bench::opencv_edt_differ_px(mask);
  if (differ < 0) state.SkipWithError("failed");
  state.counters["differ_px"] = static_cast<double>(differ);
  for (auto _ : state) {
    cv::distanceTransform(m, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE, CV_32F);
    benchmark::DoNotOptimize(dist.data);
  }
  state.counters["pixels/s"] = benchmark::Counter(static_cast<double>(w) * h,
                                                  benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(opencv_edt<false>)->Name("opencv_edt_precise/tree")->Args({640, 480})
    ->Args({1920, 1080})->Args({4000, 3000})->Unit(benchmark::kMillisecond);
BENCHMARK(opencv_edt<true>)->Name("opencv_edt_precise/blob50")->Args({1920, 1080})
    ->Unit(benchmark::kMillisecond);
#endif

}  // namespace

BENCHMARK_MAIN();
