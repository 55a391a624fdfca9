#!/usr/bin/env bash
# SPDX-License-Identifier: BSL-1.0
# Runs every libFuzzer target for SECONDS each (default 60) with clang 16, ASan and UBSan.
# Seeds come from the sample masks (examples/data/) and tests/fuzz/corpus/; findings are written
# to build/fuzz/findings/<target>/ (each run's whole log to build/fuzz/<target>.log) and should
# become regression tests. Every target runs even when an earlier one found something; the exit
# status is 1 if any did. An input that runs longer than 10 s counts as a finding (an endless
# loop). CMAKE_BUILD_PARALLEL_LEVEL limits the build's jobs.
# Usage: scripts/fuzz.sh [SECONDS] [target ...]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds="${1:-60}"
shift || true
scripts/install-deps.sh clang-16
cmake -S . -B build/fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_CXX_COMPILER=clang++-16 -DPERCH_BUILD_FUZZERS=ON -DPERCH_BUILD_TESTS=OFF \
  -DPERCH_BUILD_EXAMPLES=OFF -DPERCH_BUILD_BENCHMARKS=OFF -DPERCH_INSTALL=OFF >/dev/null
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(fuzz_png fuzz_find_perch fuzz_skeleton_graph fuzz_tracker)
cmake --build build/fuzz --target "${targets[@]}"
found=0
for t in "${targets[@]}"; do
  corpus="build/fuzz/corpus/$t"
  findings="build/fuzz/findings/$t"
  mkdir -p "$corpus" "$findings"
  # Seeds: the sample PNGs for the PNG reader; the same files' bytes drive the other targets.
  cp -n examples/data/*.png "$corpus"/ 2>/dev/null || true
  [ -d "tests/fuzz/corpus/$t" ] && cp -n "tests/fuzz/corpus/$t"/* "$corpus"/ 2>/dev/null || true
  echo "== $t: ${seconds}s"
  "build/fuzz/tests/fuzz/$t" -max_total_time="$seconds" -timeout=10 -print_final_stats=1 \
    -artifact_prefix="$findings/" -max_len=65536 "$corpus" 2>&1 | tee "build/fuzz/$t.log" |
    grep -E "^(stat::|==|SUMMARY|Done|#[0-9]+[[:space:]]+DONE|ALARM|Test unit written)|runtime error|deadly signal" ||
    true
  if compgen -G "$findings/*" >/dev/null; then
    echo "perch: $t found crashes: $findings" >&2
    found=1
  fi
done
exit "$found"
