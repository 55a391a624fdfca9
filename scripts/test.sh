#!/usr/bin/env bash
# SPDX-License-Identifier: BSL-1.0
# Builds and runs every test: installs missing Debian packages, then the `test` workflow
# (warnings as errors, consumer projects, header self-containment, the host's site hashes),
# then the `firmware` workflow (-fno-exceptions -fno-rtti), then the `asan` workflow
# (AddressSanitizer + UBSan, no recover) over the whole suite; then the cross targets: the
# Cortex-M7 firmware image (linked, symbols and size checked, run on qemu-system-arm), and a
# subset of the tests plus the site hashes on aarch64 and armhf under qemu-user.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
export CTEST_PARALLEL_LEVEL="${CTEST_PARALLEL_LEVEL:-$(nproc)}"
export CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-$(nproc)}"
cmake --workflow --preset test
cmake --workflow --preset firmware
cmake --workflow --preset asan
cmake --workflow --preset cortex-m7
cmake --workflow --preset aarch64
cmake --workflow --preset armhf
