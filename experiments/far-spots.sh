#!/usr/bin/env bash
# experiments/far-spots.sh MESH... [-- OUT_DIR]
# Where the full geometry image's Hausdorff distance comes from. For each mesh: the default
# bake's full-resolution image as a mesh (ngi-bake --export-mesh), its distance to the input
# (ngi-eval distance, with a heat map), then the farthest sample of each direction located in
# the image: its chart, its distance from the chart's border in samples, and the local sample
# spacing there (the largest distance to a grid neighbour) against the chart's median spacing.
# Prints one Markdown row per mesh; OUT_DIR (default /tmp/ngi-far-spots) keeps the bakes, the
# JSON files and the heat maps. Needs a finished build (bash tools/build.sh) and python3.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
meshes=(); out=/tmp/ngi-far-spots
while [ $# -gt 0 ]; do
  if [ "$1" = "--" ]; then out="${2:?-- expects OUT_DIR}"; break; fi
  meshes+=("$1"); shift
done
[ ${#meshes[@]} -gt 0 ] || { echo "usage: $0 MESH... [-- OUT_DIR]" >&2; exit 2; }
mkdir -p "$out"
echo "| mesh | charts | HD x1e-2 | p99 image->input / input->image x1e-2 | farthest image sample | farthest input sample |"
echo "|---|---|---|---|---|---|"
for mesh in "${meshes[@]}"; do
  name="$(basename "${mesh%.*}")"
  "$here/build/bin/ngi-bake" "$mesh" -o "$out/$name.ngi" --export-mesh "$out/$name.ply" --json "$out/$name.bake.json" --quiet
  "$here/build/bin/ngi-eval" distance "$mesh" "$out/$name.ply" --json="$out/$name.distance.json" \
    --heat-map "$out/$name.heat.png" > /dev/null
  python3 - "$name" "$out" <<'PY'
import json, math, statistics, sys
name, out = sys.argv[1], sys.argv[2]
d = json.load(open(f"{out}/{name}.distance.json"))
res = [c["resolution"] for c in json.load(open(f"{out}/{name}.bake.json"))["charts"]]
with open(f"{out}/{name}.ply", "rb") as f:
    n = 0
    while True:
        line = f.readline().decode()
        if line.startswith("element vertex"): n = int(line.split()[2])
        if line.startswith("end_header"): break
    v = [tuple(map(float, f.readline().split())) for _ in range(n)]
starts = [0]
for r in res: starts.append(starts[-1] + (r + 1) ** 2)
scale = d["frame"]["scale"]
row = f"| {name} | {len(res)} | {d['hausdorff_x1e-2']:.3f} | {d['p99_candidate_to_reference']*100:.4f} / {d['p99_reference_to_candidate']*100:.4f} |"
for key in ("farthest_candidate_sample", "farthest_reference_sample"):
    p = d[key]
    best = min(range(len(v)), key=lambda i: (v[i][0]-p[0])**2 + (v[i][1]-p[1])**2 + (v[i][2]-p[2])**2)
    c = max(j for j in range(len(res)) if starts[j] <= best)
    R = res[c]; y, x = divmod(best - starts[c], R + 1)
    at = lambda xx, yy: v[starts[c] + yy * (R + 1) + xx]
    local = max(math.dist(v[best], at(xx, yy)) for xx, yy in ((x-1, y), (x+1, y), (x, y-1), (x, y+1)) if 0 <= xx <= R and 0 <= yy <= R)
    step = max(1, R // 64)
    median = statistics.median(math.dist(at(xx, yy), at(xx + 1, yy)) for yy in range(0, R + 1, step) for xx in range(0, R, step))
    row += f" chart {c} ({R}^2), {min(x, y, R - x, R - y)} samples from its border, spacing {local*scale*100:.3f}% = {local/median:.1f}x the median |"
print(row, flush=True)
PY
done
