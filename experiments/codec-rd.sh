#!/usr/bin/env bash
# Rate-distortion of the nested-pyramid position coder: for each baked asset
# (stored at a fine level, e.g. ngi-bake --store-res 256), each stored size and each step,
# the position bytes (ngi-bench-codec) and the CD (x1e-4) of the LoD-0 surface restored by
# bicubic upsampling from the DECODED level, against the input mesh (ngi-eval distance).
#   bash experiments/codec-rd.sh ASSET.ngi:MESH.off... [-- SIZES STEPS]
# Defaults: CODEC_RD_SIZES=257,129,65,33 CODEC_RD_STEPS=16,64,256,1024 (1/65536 of the box),
# CODEC_RD_TANGENT=0. Prints a Markdown table.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/bin"
sizes="${CODEC_RD_SIZES:-257,129,65,33}"
steps="${CODEC_RD_STEPS:-16,64,256,1024}"
tangent="${CODEC_RD_TANGENT:-0}"  # --tangent-scale of ngi-bench-codec (0: xyz residuals)
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
echo "| mesh | size | step | POSI bytes | bits/sample | CD bicubic x1e-4 |"
echo "|---|---|---|---|---|---|"
for pair in "$@"; do
  asset="${pair%%:*}"; mesh="${pair#*:}"
  name="$(basename "${asset%.*}")"
  "$bin/ngi-bench-codec" "$asset" --sizes "$sizes" --steps "$steps" --normal-bits 0 --tangent-scale "$tangent" --write "$out" > "$out/table.md"
  grep "^| $name |" "$out/table.md" | while IFS='|' read -r _ n size step bytes bps _; do
    size=$(echo $size); step=$(echo $step); k="$step"
    "$bin/ngi-eval" mesh "$out/${name}_s${size}_k${k}.ngi" --lod 0 --bicubic -o "$out/lod0.ply" > /dev/null
    cd=$("$bin/ngi-eval" distance "$mesh" "$out/lod0.ply" --json | grep -o '"chamfer_x1e-4": *[-0-9.e+]*' | sed 's/.*: *//')
    printf "| %s | %s | %s | %s | %s | %.4g |\n" "$name" "$size" "$step" $bytes $bps "$cd"
  done
done
