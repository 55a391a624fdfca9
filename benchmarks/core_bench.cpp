// SPDX-License-Identifier: BSL-1.0
// Core view operations: the cost of one read of a mask through a strided view, the floor every
// pipeline stage is measured against.
#include <benchmark/benchmark.h>

#include <cstdint>
#include <vector>

#include "perch/core.hpp"

namespace {

void count_foreground(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const int height = static_cast<int>(state.range(1));
  std::vector<std::uint8_t> pixels(static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = (i * 2654435761u >> 13) % 7 == 0;
  const perch::image_view<const std::uint8_t> view(pixels.data(), width, height);
  for (auto _ : state) {
    std::size_t count = 0;
    for (int y = 0; y < view.height(); ++y)
      for (const std::uint8_t p : view.row(y)) count += p != 0;
    benchmark::DoNotOptimize(count);
  }
  state.counters["pixels/s"] = benchmark::Counter(
      static_cast<double>(view.size()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(count_foreground)->Args({640, 480})->Args({1920, 1080})->Args({4000, 3000})
    ->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
