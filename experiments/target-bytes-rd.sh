#!/usr/bin/env bash
# The rate-distortion table of `ngi-bake --target-bytes`: for each mesh and budget,
# bake at that budget, then the bytes per chunk (the bake's --json) and the CD (x1e-4) of the
# LoD-0 surface restored by bicubic upsampling against the input mesh (ngi-eval distance).
#   bash experiments/target-bytes-rd.sh MESH... [-- BUDGETS]     (BUDGETS default 4096,8192,16384,32768,65536)
# OUT_DIR = $TARGET_BYTES_OUT (default out/target-bytes). Prints a Markdown table.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/bin"
budgets="${TARGET_BYTES_BUDGETS:-4096,8192,16384,32768,65536}"
out="${TARGET_BYTES_OUT:-$root/out/target-bytes}"
mkdir -p "$out"
echo "| mesh | budget | asset bytes | POSI | NORM | META | other | stored | step | CD bicubic x1e-4 | HD x1e-2 |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for mesh in "$@"; do
  name="$(basename "${mesh%.*}")"
  for budget in ${budgets//,/ }; do
    asset="$out/${name}_$budget.ngi"; json="$out/${name}_$budget.json"
    "$bin/ngi-bake" "$mesh" -o "$asset" --target-bytes "$budget" --json "$json" --quiet >&2
    "$bin/ngi-eval" mesh "$asset" --lod 0 --bicubic -o "$out/lod0.ply" > /dev/null
    "$bin/ngi-eval" distance "$mesh" "$out/lod0.ply" --json > "$out/${name}_$budget.distance.json"
    python3 - "$json" "$out/${name}_$budget.distance.json" "$name" "$budget" <<'PY'
import json, sys
b = json.load(open(sys.argv[1])); d = json.load(open(sys.argv[2]))
c = b["chunkBytes"]; other = b["assetBytes"] - c.get("POSI", 0) - c.get("NORM", 0) - c.get("META", 0)
r = b["rateControl"]
print(f"| {sys.argv[3]} | {sys.argv[4]} | {b['assetBytes']} | {c.get('POSI', 0)} | {c.get('NORM', 0)} | {c.get('META', 0)} | {other} | "
      f"{b['storeResolution'] + 1}^2 | {r['positionStep']}/65536 | {d['chamfer_x1e-4']:.4g} | {d['hausdorff_x1e-2']:.3g} |")
PY
  done
done
