// SPDX-License-Identifier: BSL-1.0
// `scripts/ab.sh`: two revisions of perch in one binary, their `find_perch` calls interleaved
// (a, b, then b, a, …) so that a shared machine's slow minutes fall on both; prints per stage
// the median of each and the median of the paired differences, and whether both give the same
// results (`AB_HASH` of each side).
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

void run_a(int w, int h, bool noisy, float* out);
void run_b(int w, int h, bool noisy, float* out);
std::uint64_t hash_a();
std::uint64_t hash_b();

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: ab WIDTH HEIGHT CALLS [noisy]\n");
    return 2;
  }
  const int w = std::atoi(argv[1]);
  const int h = std::atoi(argv[2]);
  const int calls = std::atoi(argv[3]);
  const bool noisy = argc > 4 && std::atoi(argv[4]) != 0;
  if (w < 16 || h < 16 || calls < 1) return 2;
  const std::uint64_t ha = hash_a();
  const std::uint64_t hb = hash_b();
  std::printf("results: a %016llx, b %016llx: %s\n", static_cast<unsigned long long>(ha),
              static_cast<unsigned long long>(hb), ha == hb ? "same" : "DIFFERENT");
  float a[8];
  float b[8];
  for (int warm = 0; warm < 2; ++warm) {  // trees made, workspaces grown and touched
    run_a(w, h, noisy, a);
    run_b(w, h, noisy, b);
  }
  std::vector<float> as[8], bs[8], diffs[8];
  for (int i = 0; i < calls; ++i) {
    if (i % 2 == 0) {
      run_a(w, h, noisy, a);
      run_b(w, h, noisy, b);
    } else {
      run_b(w, h, noisy, b);
      run_a(w, h, noisy, a);
    }
    for (int k = 0; k < 8; ++k) {
      as[k].push_back(a[k]);
      bs[k].push_back(b[k]);
      diffs[k].push_back(b[k] - a[k]);
    }
  }
  auto median = [](std::vector<float> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
  };
  const char* stage[8] = {"total", "prepare", "distance", "skeleton",
                          "graph", "prune",   "windows",  "ranking"};
  std::printf("%d x %d %s, %d interleaved calls, medians (ms):\n", w, h, noisy ? "noisy" : "clean",
              calls);
  std::printf("%-9s %9s %9s %9s\n", "stage", "a", "b", "b - a");
  for (int k = 0; k < 8; ++k)
    std::printf("%-9s %9.3f %9.3f %+9.3f\n", stage[k], median(as[k]), median(bs[k]),
                median(diffs[k]));
  return ha == hb ? 0 : 1;
}
