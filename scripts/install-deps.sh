#!/usr/bin/env bash
# SPDX-License-Identifier: BSL-1.0
# Installs the Debian 12 packages perch's build needs that this machine lacks: with apt-get when
# run as root (or through sudo when available), else prints the exact command to run.
# Usage: scripts/install-deps.sh [--demo] [extra-package ...]
#   --demo: only what the demo needs (the library, the perch tool), not the test frameworks.
set -euo pipefail

packages=(cmake ninja-build g++ libeigen3-dev zlib1g-dev)
if [ "${1:-}" = "--demo" ]; then
  shift
else
  # The test frameworks; the cross compilers and qemu build and run the aarch64, armhf and
  # Cortex-M7 targets.
  packages+=(doctest-dev libbenchmark-dev
             g++-aarch64-linux-gnu g++-arm-linux-gnueabihf gcc-arm-none-eabi
             libstdc++-arm-none-eabi-newlib qemu-user qemu-system-arm)
fi
packages+=("$@")
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed' || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "perch: installing missing packages: ${missing[*]}" >&2
if [ "$(id -u)" -eq 0 ]; then
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
elif command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
  sudo apt-get update -qq
  sudo DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
else
  echo "perch: please run:  sudo apt-get install -y ${missing[*]}" >&2
  exit 1
fi
