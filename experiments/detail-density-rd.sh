#!/usr/bin/env bash
# Does a target density that follows detail beat the area measure? For each
# mesh and strength S, `ngi-bake --detail-density S` at a fixed stored level (--store-res,
# default 256: the 257^2 level of 1025^2) or at a byte budget (DETAIL_BUDGET=N: --target-bytes
# N), then the CD/HD (x1e-4 / x1e-2) against the input of the full image as baked
# (--export-mesh: the sampling alone) and of the LoD-0 surface restored bicubically.
#   bash experiments/detail-density-rd.sh MESH... [-- STRENGTHS]   (STRENGTHS default 0,1,3)
# OUT_DIR = $DETAIL_OUT (default out/detail-density). Prints a Markdown table.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/bin"
meshes=()
strengths="0,1,3"
while [ $# -gt 0 ]; do
  if [ "$1" = "--" ]; then strengths="$2"; shift 2; continue; fi
  meshes+=("$1"); shift
done
out="${DETAIL_OUT:-$root/out/detail-density}"
store="${DETAIL_STORE_RES:-256}"
if [ -n "${DETAIL_BUDGET:-}" ]; then level=(--target-bytes "$DETAIL_BUDGET"); else level=(--store-res "$store"); fi
mkdir -p "$out"
echo "| mesh | S | asset bytes | stored | full image CD | full image HD | LoD-0 bicubic CD | LoD-0 HD | undersampled area | bake s |"
echo "|---|---|---|---|---|---|---|---|---|---|"
for mesh in "${meshes[@]}"; do
  name="$(basename "${mesh%.*}")"
  for s in ${strengths//,/ }; do
    base="$out/${name}_S$s"
    "$bin/ngi-bake" "$mesh" -o "$base.ngi" "${level[@]}" --detail-density "$s" --export-mesh "$base.full.ply" \
      --json "$base.json" --quiet >&2
    "$bin/ngi-eval" distance "$mesh" "$base.full.ply" --json > "$base.full.json"
    "$bin/ngi-eval" mesh "$base.ngi" --lod 0 --bicubic -o "$base.lod0.ply" > /dev/null
    "$bin/ngi-eval" distance "$mesh" "$base.lod0.ply" --json > "$base.lod0.json"
    python3 - "$base" "$name" "$s" <<'PY'
import json, sys
base, name, s = sys.argv[1:]
b = json.load(open(base + ".json")); f = json.load(open(base + ".full.json")); l = json.load(open(base + ".lod0.json"))
print(f"| {name} | {s} | {b['assetBytes']} | {b['storeResolution'] + 1}^2 | {f['chamfer_x1e-4']:.4g} | {f['hausdorff_x1e-2']:.3g} | "
      f"{l['chamfer_x1e-4']:.4g} | {l['hausdorff_x1e-2']:.3g} | {b['parameterization']['undersampledAreaFraction']:.3g} | {b['totalSeconds']:.1f} |")
PY
  done
done
