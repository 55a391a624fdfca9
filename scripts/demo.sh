#!/usr/bin/env bash
# SPDX-License-Identifier: BSL-1.0
# The main job: installs missing Debian packages, builds the perch tool and runs it on the
# sample masks in examples/data/, writing JSON and annotated PNGs to build/demo/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh --demo
export CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}"
cmake --workflow --preset demo
