#!/usr/bin/env bash
# SPDX-License-Identifier: BSL-1.0
# A/B timing of a change: `scripts/ab.sh [REV] [WIDTH HEIGHT CALLS [noisy]]` compiles perch at
# REV (default HEAD) as side a and the working tree as side b into one binary
# (benchmarks/ab/), checks that both give the same results over 44 synthetic trees, and times
# `find_perch` on the benchmark tree (default 4000 3000, 40 calls each), the two sides'
# calls interleaved so that the host's noise falls on both. Exit status 1 when the results
# differ. Needs g++ and libeigen3-dev (scripts/install-deps.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
rev="${1:-HEAD}"
shift || true
args=("${@:-4000 3000 40}")
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/a"
git archive "$rev" include | tar -x -C "$work/a"
flags=(-std=c++20 -O3 -DNDEBUG -I examples/support -I /usr/include/eigen3)
c++ "${flags[@]}" -I "$work/a/include" -Dperch=perch_a -DAB_RUN=run_a -DAB_HASH=hash_a \
  -c benchmarks/ab/ab_side.cpp -o "$work/a.o" &
side_a=$!
c++ "${flags[@]}" -I include -Dperch=perch_b -DAB_RUN=run_b -DAB_HASH=hash_b \
  -c benchmarks/ab/ab_side.cpp -o "$work/b.o"
wait "$side_a"
c++ -O2 benchmarks/ab/ab_main.cpp "$work/a.o" "$work/b.o" -o "$work/ab"
echo "a: $rev ($(git rev-parse --short "$rev")), b: the working tree"
# shellcheck disable=SC2068
"$work/ab" ${args[@]}
