#!/usr/bin/env bash
# Applies the tree's C++ style (.clang-format, clang-format-14) to every tracked .cpp and .h,
# or with --check changes nothing and fails, listing the files that differ (CI runs this).
# GLSL is not formatted (clang-format does not know its qualifiers).
set -euo pipefail
cd "$(dirname "$0")/.."
formatter=$(command -v clang-format-14 || command -v clang-format || true)
[ -n "$formatter" ] || { echo "format.sh: clang-format-14 is not installed (Debian: clang-format-14)" >&2; exit 2; }
mapfile -t files < <(git ls-files '*.cpp' '*.h')
if [ "${1:-}" = "--check" ]; then
    bad=()
    for f in "${files[@]}"; do
        "$formatter" --style=file "$f" | cmp -s - "$f" || bad+=("$f")
    done
    if [ ${#bad[@]} -gt 0 ]; then
        printf 'format.sh: not formatted (run bash tools/format.sh): %s\n' "${bad[@]}" >&2
        exit 1
    fi
    echo "format.sh: ${#files[@]} files formatted"
else
    "$formatter" --style=file -i "${files[@]}"
fi
