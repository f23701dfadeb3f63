#!/usr/bin/env bash
# The main job, end to end: installs dependencies, builds ngi, BAKES the default mesh
# (bunny00 from Debian's libcgal-demo data: remesh, cut, Ricci flow, optimal transport,
# 1025^2 geometry image, 129^2 level stored), then RESTORES it on the GPU and RENDERS frames
# at several levels of detail plus a contact sheet of every level, headless, into ./out.
# Idempotent. `bash tools/demo.sh path/to/asset.ngi` renders an existing asset instead.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/tools/build.sh"
out="$root/out"
mkdir -p "$out"
bin="$root/build/bin"
if [ $# -ge 1 ]; then
  asset="$1"
else
  meshes="$("$root/tools/fetch-data.sh")"
  asset="$out/bunny00.ngi"
  "$bin/ngi-bake" "$meshes/bunny00.off" -o "$asset" --json "$out/bunny00.json"
fi
name="$(basename "$asset" .ngi)"
# The full resolution is restored from the stored level by the shipped x8 network
# (assets/sr-x8.ngiw, GLSL compute); one LoD-0 frame without it (bilinear) for comparison.
sr=(--sr --weights "$root/assets/sr-x8.ngiw")
for lod in 0 1.5 3 5; do
  "$bin/ngi-render" "$asset" -o "$out/${name}_lod$lod.png" --lod "$lod" --size 800x800 --yaw 0 --pitch 10 "${sr[@]}"
done
"$bin/ngi-render" "$asset" -o "$out/${name}_lod0_bilinear.png" --lod 0 --size 800x800 --yaw 0 --pitch 10 --no-sr
"$bin/ngi-render" "$asset" -o "$out/${name}_wireframe_lod4.png" --lod 4 --mode wireframe --size 800x800 --yaw 0 --pitch 10 "${sr[@]}"
"$bin/ngi-render" "$asset" -o "$out/${name}_contact_sheet.png" --contact-sheet --size 320x320 --mode lod --yaw 0 --pitch 10 "${sr[@]}"
echo "frames written to $out"
