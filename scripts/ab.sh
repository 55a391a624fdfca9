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
# side NAME INCLUDE: ab_side.cpp and the synthetic trees it draws (perch_support's
# synthetic_tree.cpp), both with perch's namespace renamed to perch_NAME.
side() {
  local defs=(-I "$2" "-Dperch=perch_$1" "-DAB_RUN=run_$1" "-DAB_HASH=hash_$1")
  c++ "${flags[@]}" "${defs[@]}" -c benchmarks/ab/ab_side.cpp -o "$work/$1.o"
  c++ "${flags[@]}" "${defs[@]}" -c examples/support/support/synthetic_tree.cpp -o "$work/$1-tree.o"
}
side a "$work/a/include" &
side_a=$!
side b include
wait "$side_a"
c++ -O2 benchmarks/ab/ab_main.cpp "$work/a.o" "$work/a-tree.o" "$work/b.o" "$work/b-tree.o" \
  -o "$work/ab"
echo "a: $rev ($(git rev-parse --short "$rev")), b: the working tree"
# shellcheck disable=SC2068
"$work/ab" ${args[@]}
