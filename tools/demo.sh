#!/usr/bin/env bash
# The main job, end to end: installs dependencies, builds ngi, BAKES the default mesh
# (bunny00 from Debian's libcgal-demo data: remesh, cut, Ricci flow, optimal transport,
# 1025^2 geometry image; --target-bytes 16384 picks the stored level and the quantization so
# the asset fits 16 KB), then RESTORES it on the GPU and RENDERS frames at several levels of
# detail plus a contact sheet of every level, headless, into ./out.
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
  "$bin/ngi-bake" "$meshes/bunny00.off" -o "$asset" --target-bytes 16384 --json "$out/bunny00.json"
fi
name="$(basename "$asset" .ngi)"
# The full resolution is restored from the stored level on the GPU by the tools' default: the
# shipped network the asset names (assets/*.ngiw, GLSL compute) when there is one for its
# stored level, else bicubically; one LoD-0 frame restored bilinearly (--no-sr) for comparison.
for lod in 0 1.5 3 5; do
  "$bin/ngi-render" "$asset" -o "$out/${name}_lod$lod.png" --lod "$lod" --size 800x800 --yaw 0 --pitch 10
done
"$bin/ngi-render" "$asset" -o "$out/${name}_lod0_bilinear.png" --lod 0 --size 800x800 --yaw 0 --pitch 10 --no-sr
"$bin/ngi-render" "$asset" -o "$out/${name}_wireframe_lod4.png" --lod 4 --mode wireframe --size 800x800 --yaw 0 --pitch 10
"$bin/ngi-render" "$asset" -o "$out/${name}_contact_sheet.png" --contact-sheet --size 320x320 --mode lod --yaw 0 --pitch 10
# Adaptive: each tile at the coarsest level within 1 pixel, and the same frame's tiles coloured by level.
"$bin/ngi-render" "$asset" -o "$out/${name}_adaptive.png" --max-error-px 1 --size 800x800 --yaw 0 --pitch 10
"$bin/ngi-render" "$asset" -o "$out/${name}_adaptive_tiles.png" --max-error-px 1 --mode lod --size 800x800 --yaw 0 --pitch 10
echo "frames written to $out"
