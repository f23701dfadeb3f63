#!/usr/bin/env bash
# tools/fuzz.sh [SECONDS] [TARGET...] | tools/fuzz.sh --build-only
# Builds the libFuzzer targets (fuzz/, clang-14, ASan + UBSan + libFuzzer, the whole tree
# instrumented) into build-fuzz and runs each for SECONDS (default 30; `tools/fuzz.sh 3600`
# for a long run), as many at once as there are cores, from the committed seeds in
# fuzz/corpus/<target>/ (new inputs go to build-fuzz/corpus/<target>/, never into the tree).
# Fails if any target crashes, leaks, times out (> 20 s on one input), runs out of memory
# (> 2 GB) or breaks an invariant; the input is kept as build-fuzz/crashes/<target>-*.
# Targets: asset_fuzzer weights_fuzzer mesh_{obj,off,ply,stl,gltf,glb}_fuzzer (default: all).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build-fuzz"
all=(asset_fuzzer weights_fuzzer mesh_obj_fuzzer mesh_off_fuzzer mesh_ply_fuzzer mesh_stl_fuzzer mesh_gltf_fuzzer mesh_glb_fuzzer)
build_only=0
seconds=30
if [ "${1:-}" = --build-only ]; then build_only=1; shift; elif [ $# -gt 0 ]; then seconds="$1"; shift; fi
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=("${all[@]}")
start=$SECONDS
"$root/tools/install-deps.sh"

flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer"
cmake -S "$root" -B "$build" -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 \
      -DCMAKE_BUILD_TYPE=Debug -DCMAKE_C_FLAGS_DEBUG="-g -O1" -DCMAKE_CXX_FLAGS_DEBUG="-g -O1" \
      -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" \
      -DNGI_FUZZ=ON -DNGI_WARNINGS_AS_ERRORS=ON -DNGI_BUILD_OFFLINE=OFF -DNGI_BUILD_TESTS=OFF -DCGAL_DO_NOT_WARN_ABOUT_CMAKE_BUILD_TYPE=TRUE >/dev/null
cmake --build "$build" -j"$(nproc)" --target "${targets[@]}" ngi-fuzz-seeds
echo "fuzz: build $((SECONDS - start)) s"
[ $build_only = 1 ] && exit 0

export ASAN_OPTIONS=detect_leaks=1:strict_string_checks=1
export UBSAN_OPTIONS=print_stacktrace=1
# Readable stacks: Debian installs the symbolizer under a versioned name.
[ -x /usr/lib/llvm-14/bin/llvm-symbolizer ] && export ASAN_SYMBOLIZER_PATH=/usr/lib/llvm-14/bin/llvm-symbolizer
mkdir -p "$build/crashes" "$build/logs"
run_one() {  # TARGET: one fuzzing session, its log in build-fuzz/logs/TARGET.log
    local target="$1" format dict=()
    format="${target#mesh_}"; format="${format%_fuzzer}"
    [ "$format" = glb ] && format=gltf  # the JSON chunk holds the same keys
    [ -f "$root/fuzz/dict/$format.dict" ] && dict=(-dict="$root/fuzz/dict/$format.dict")
    mkdir -p "$build/corpus/$target"
    "$build/bin/$target" -max_total_time="$seconds" -timeout=20 -rss_limit_mb=2048 -print_final_stats=1 \
        -artifact_prefix="$build/crashes/$target-" "${dict[@]}" \
        "$build/corpus/$target" "$root/fuzz/corpus/$target" > "$build/logs/$target.log" 2>&1
}
failed=()
pids=()
names=()
slots="$(nproc)"
finish() {  # waits for the oldest running session and records its result
    local pid="${pids[0]}" name="${names[0]}"
    pids=("${pids[@]:1}"); names=("${names[@]:1}")
    if wait "$pid"; then
        echo "fuzz: $name clean ($(grep -o 'stat::number_of_executed_units: *[0-9]*' "$build/logs/$name.log" | grep -o '[0-9]*$') runs)"
    else
        failed+=("$name")
        echo "fuzz: $name FAILED (log: $build/logs/$name.log)"
        grep -E -A 30 '^==[0-9]+==ERROR|runtime error|invariant failed|ALARM|out-of-memory|deadly signal' "$build/logs/$name.log" | head -n 60 || true
        ls "$build/crashes/$name-"* 2>/dev/null || true
    fi
}
for target in "${targets[@]}"; do
    [ ${#pids[@]} -ge "$slots" ] && finish
    run_one "$target" &
    pids+=($!); names+=("$target")
done
while [ ${#pids[@]} -gt 0 ]; do finish; done
if [ ${#failed[@]} -gt 0 ]; then
    echo "fuzz: ${#failed[@]} target(s) failed: ${failed[*]} ($((SECONDS - start)) s)"
    exit 1
fi
echo "fuzz: every target clean, ${seconds} s each ($((SECONDS - start)) s)"
