#!/usr/bin/env bash
# Builds core + engine with AddressSanitizer/UBSan (Debug) into build-asan and runs their
# tests and one ngi-render capture with leak detection. The Vulkan driver is preloaded so
# that its own allocations are attributed to it (and suppressed) rather than to an
# unloaded "unknown module" after vkDestroyInstance.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build-asan"
cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Debug -DNGI_SANITIZE=ON -DNGI_BUILD_OFFLINE=OFF >/dev/null
cmake --build "$build" -j"$(nproc)" --target ngi_core_tests ngi_engine_tests ngi-render
supp="$(mktemp)"
printf 'leak:libvulkan_lvp\nleak:libLLVM\nleak:libvulkan.so\nleak:libVkLayer_khronos_validation\n' > "$supp"
driver="$(ls /usr/lib/*/libvulkan_lvp.so | head -n 1)"
export LD_PRELOAD="$(gcc -print-file-name=libasan.so) $driver"
export ASAN_OPTIONS=detect_leaks=1 LSAN_OPTIONS="suppressions=$supp"
"$build/bin/ngi_core_tests"
"$build/bin/ngi_engine_tests"
"$build/bin/ngi-render" "$root/assets/default.ngi" -o "$build/asan_capture.png" --contact-sheet --size 128x128 --validation
rm -f "$supp"
echo "sanitizer run clean"
