#!/usr/bin/env bash
# Regenerates the committed seed corpora fuzz/corpus/<target>/ with ngi-fuzz-seeds
# (fuzz/make_seeds.cpp, built in build-fuzz by tools/fuzz.sh): tiny valid inputs, a few
# hundred bytes each. Regression inputs committed beside them (names starting with
# "regression-") are kept.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/tools/fuzz.sh" --build-only ngi-fuzz-seeds
"$root/build-fuzz/bin/ngi-fuzz-seeds" "$root/fuzz/corpus"
du -sb "$root/fuzz/corpus"/* | sed 's|'"$root"'/||'
