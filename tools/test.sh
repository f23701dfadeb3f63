#!/usr/bin/env bash
# Builds ngi and runs the whole test suite with ctest (Vulkan tests on lavapipe or any
# device, validation layer on).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/tools/build.sh"
cd "$root/build"
ctest --output-on-failure -j"$(nproc)"
