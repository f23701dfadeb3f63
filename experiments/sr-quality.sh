#!/usr/bin/env bash
# The super-resolution quality table: for each mesh, the full-resolution
# geometry image's mesh (ground truth) against the LoD-0 mesh restored from the stored level
# by bilinear upsampling, bicubic (Catmull-Rom) upsampling and the network; CD (x1e-4) and
# HD (x1e-2) by `ngi-eval distance` (DESIGN.md's metric).
#   bash experiments/sr-quality.sh WEIGHTS.ngiw MESH.off... [-- OUT_DIR]
# Defaults: the development evaluation set of DESIGN.md, OUT_DIR = out/sr-quality. Bakes each
# mesh once (reused if OUT_DIR/NAME.ngi exists). Prints a Markdown table.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/bin"
weights="${1:?usage: sr-quality.sh WEIGHTS.ngiw [MESH...]}"
shift
meshes=("$@")
if [ ${#meshes[@]} -eq 0 ]; then
  data="$("$root/tools/fetch-data.sh")"
  meshes=("$data/fandisk.off" "$data/elephant.off" "$data/knot1.off" "$data/mushroom.off" "$data/elk.off")
fi
out="${SR_QUALITY_OUT:-$root/out/sr-quality}"
mkdir -p "$out"
field() { grep -o "\"$1\": *[-0-9.e+]*" | head -1 | sed 's/.*: *//'; }
echo "| mesh | bilinear CD | bicubic CD | network CD | bilinear HD | bicubic HD | network HD | CD margin vs best | HD margin vs best |"
echo "|---|---|---|---|---|---|---|---|---|"
for mesh in "${meshes[@]}"; do
  name="$(basename "${mesh%.*}")"
  if [ ! -f "$out/$name.ngi" ] || [ ! -f "$out/${name}_full.ply" ]; then
    "$bin/ngi-bake" "$mesh" -o "$out/$name.ngi" --export-mesh "$out/${name}_full.ply" --quiet >&2
  fi
  declare -A cd hd
  for restore in bilinear bicubic network; do
    case $restore in
      bilinear) flags=(--no-sr) ;;
      bicubic) flags=(--bicubic) ;;
      network) flags=(--sr --weights "$weights") ;;
    esac
    "$bin/ngi-eval" mesh "$out/$name.ngi" --lod 0 "${flags[@]}" -o "$out/${name}_$restore.ply" >&2
    json="$("$bin/ngi-eval" distance "$out/${name}_full.ply" "$out/${name}_$restore.ply" --json)"
    cd[$restore]="$(echo "$json" | field chamfer_x1e-4)"
    hd[$restore]="$(echo "$json" | field hausdorff_x1e-2)"
  done
  awk -v n="$name" -v c1="${cd[bilinear]}" -v c2="${cd[bicubic]}" -v c3="${cd[network]}" \
      -v h1="${hd[bilinear]}" -v h2="${hd[bicubic]}" -v h3="${hd[network]}" 'BEGIN {
    cb = c1 < c2 ? c1 : c2; hb = h1 < h2 ? h1 : h2;
    printf "| %s | %.4g | %.4g | %.4g | %.4g | %.4g | %.4g | %+.1f%% | %+.1f%% |\n", n, c1, c2, c3, h1, h2, h3,
           100 * (c3 - cb) / cb, 100 * (h3 - hb) / hb }'
done
