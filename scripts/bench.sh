#!/usr/bin/env bash
# SPDX-License-Identifier: BSL-1.0
# Benchmarks: installs missing Debian packages (OpenCV too, for side-by-side timings of its
# kernels), then the `bench` workflow: Release, every benchmark executable one after another
# (one thread each), output printed.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh libopencv-dev libopencv-contrib-dev
export CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}"
cmake --workflow --preset bench
