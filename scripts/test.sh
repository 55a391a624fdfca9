#!/usr/bin/env bash
# SPDX-License-Identifier: BSL-1.0
# Builds and runs every test: installs missing Debian packages, then the `test` workflow
# (warnings as errors, consumer projects, header self-containment), then the `firmware`
# workflow (-fno-exceptions -fno-rtti), then the `asan` workflow (AddressSanitizer + UBSan, no
# recover) over the whole suite.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
export CTEST_PARALLEL_LEVEL="${CTEST_PARALLEL_LEVEL:-$(nproc)}"
export CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}"
cmake --workflow --preset test
cmake --workflow --preset firmware
cmake --workflow --preset asan
