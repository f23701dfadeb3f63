#!/usr/bin/env bash
# Does splitting one surface into several charts pay (docs/cross-chart-seams.md section
# 9)? For each mesh and piece count K, `ngi-bake --split-pieces K`
# (K = 1: --no-split, one chart per component; K = auto: the closer to the input of one chart and 8) at a
# byte budget (SPLIT_BUDGET, default
# 16384: --target-bytes), then the CD/HD (x1e-4 / x1e-2) against the input of the full
# images as baked (--export-mesh: the sampling alone) and of the LoD-0 surface restored
# bicubically and by the tools' default (the network the asset names, else bicubic).
# The split pieces are not matched across charts (they crack along their borders); CD and HD
# measure the surface, not the cracks.
#   bash experiments/split-experiment.sh MESH... [-- PIECES]   (PIECES default 1,4,8; e.g. 1,8,auto)
# OUT_DIR = $SPLIT_OUT (default out/split). Prints a Markdown table; a refused bake is a row
# with its message.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/bin"
meshes=()
pieces="1,4,8"
while [ $# -gt 0 ]; do
  if [ "$1" = "--" ]; then pieces="$2"; shift 2; continue; fi
  meshes+=("$1"); shift
done
out="${SPLIT_OUT:-$root/out/split}"
budget="${SPLIT_BUDGET:-16384}"
mkdir -p "$out"
echo "| mesh | K | charts | asset bytes | stored | full image CD / HD | LoD-0 bicubic CD / HD | LoD-0 default CD / HD | max undersampled | OT it (sum) | bake s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|"
for mesh in "${meshes[@]}"; do
  name="$(basename "${mesh%.*}")"
  for k in ${pieces//,/ }; do
    base="$out/${name}_K$k"
    case "$k" in
      auto) split=(--split-pieces auto) ;;
      1) split=(--no-split) ;;
      *) split=(--split-pieces "$k") ;;
    esac
    start=$SECONDS
    if ! "$bin/ngi-bake" "$mesh" -o "$base.ngi" --target-bytes "$budget" "${split[@]}" --export-mesh "$base.full.ply" \
        --json "$base.json" --quiet 2> "$base.err" >&2; then
      echo "| $name | $k | refused: $(tail -1 "$base.err" | cut -c1-160) | | | | | | | | $((SECONDS - start)) |"
      continue
    fi
    "$bin/ngi-eval" distance "$mesh" "$base.full.ply" --json > "$base.full.json"
    "$bin/ngi-eval" mesh "$base.ngi" --lod 0 --bicubic -o "$base.lod0.ply" > /dev/null
    "$bin/ngi-eval" distance "$mesh" "$base.lod0.ply" --json > "$base.lod0.json"
    "$bin/ngi-eval" mesh "$base.ngi" --lod 0 -o "$base.lod0sr.ply" > /dev/null
    "$bin/ngi-eval" distance "$mesh" "$base.lod0sr.ply" --json > "$base.lod0sr.json"
    python3 - "$base" "$name" "$k" <<'PY'
import json, sys
base, name, k = sys.argv[1:]
b = json.load(open(base + ".json"))
d = {s: json.load(open(base + s + ".json")) for s in (".full", ".lod0", ".lod0sr")}
charts = b.get("charts", [])
under = max((c.get("parameterization", {}).get("undersampledAreaFraction", 0.0) for c in charts), default=0.0)
ot = sum(c.get("parameterization", {}).get("otIterations", 0) for c in charts)
cd = lambda s: f"{d[s]['chamfer_x1e-4']:.4g} / {d[s]['hausdorff_x1e-2']:.3g}"
print(f"| {name} | {k} | {len(charts)} | {b['assetBytes']} | {b['storeResolution'] + 1}^2 | {cd('.full')} | {cd('.lod0')} | "
      f"{cd('.lod0sr')} | {under:.3g} | {ot} | {b['totalSeconds']:.1f} |")
PY
  done
done
