#!/usr/bin/env bash
# The main job on the shipped default asset: installs dependencies, builds ngi, restores the
# asset's stored level on the GPU, builds the mip chain, and renders frames at several levels
# of detail (plus a contact sheet of every level) to PNGs in ./out. Idempotent.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/tools/build.sh"
asset="${1:-$root/assets/default.ngi}"
out="$root/out"
mkdir -p "$out"
render="$root/build/bin/ngi-render"
for lod in 0 1.5 3 5; do
  "$render" "$asset" -o "$out/default_lod$lod.png" --lod "$lod" --size 800x800
done
"$render" "$asset" -o "$out/default_wireframe_lod3.png" --lod 3 --mode wireframe --size 800x800
"$render" "$asset" -o "$out/default_contact_sheet.png" --contact-sheet --size 320x320 --mode lod
echo "frames written to $out"
