#!/usr/bin/env bash
# Installs dependencies, configures and builds ngi into ./build (Release). Idempotent.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/tools/install-deps.sh"
cmake -S "$root" -B "$root/build" -DCMAKE_BUILD_TYPE=Release -DNGI_WARNINGS_AS_ERRORS=ON >/dev/null
cmake --build "$root/build" -j"$(nproc)"
