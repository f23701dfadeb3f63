#!/usr/bin/env bash
# ngi against gltfpack at equal total bytes, geometry and colour: for each textured or coloured
# input and each budget, ngi-bake --target-bytes B, the drawn mesh at LoD 0 exported as glTF
# (ngi-eval mesh --lod 0 -o x.glb), and gltfpack (simplified -si R, meshopt-compressed -cc,
# textures re-encoded as WebP at a scale and quality) with the largest R that fits B for each
# texture setting; then ngi-eval distance of both against the input: CD, HD and colour PSNR of
# Y, Cb, Cr. Prints one Markdown table (docs/appearance.md "Measuring appearance"). An asset
# already baked in OUT is reused.
#
#   tools/peer-appearance.sh [--build DIR] [--out DIR] [--budgets 16384,65536] [--samples N] [INPUT...]
#
# The peer: gltfpack's npm build (installed here into a cache folder: it is only a comparison
# tool) has no texture codec (-tc and -tw need its native build), so its output's images are
# re-encoded by tools/peer-appearance-webp.py with cwebp (Debian's webp) and marked
# EXT_texture_webp. Texture settings tried: the input's own images, and side scale 1, 1/2, 1/4,
# 1/8, 1/16 x WebP quality 50, 85; for each, R is bisected (10 steps, -se 1: no error cap) for
# the largest file within the budget that keeps a triangle; of the settings that fit, the table
# (tools/peer-appearance-table.py) shows the one of the best Y PSNR and the one of the smallest
# CD (all are in OUT/NAME.BUDGET.peer.tsv: R, scale, quality, bytes, triangles, CD, HD, Y, Cb, Cr).
# The peer is measured on exactly its packed bytes: `gltfpack -noq` decodes the meshopt
# compression and quantization (the WebP images pass through), and ngi's reader reads that.
set -euo pipefail

root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build"
out="${TMPDIR:-/tmp}/ngi-peer-appearance"
budgets="16384,65536"
samples=100000
inputs=()
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --budgets) budgets="$2"; shift 2 ;;
    --samples) samples="$2"; shift 2 ;;
    -h|--help) sed -n '2,20p' "$0"; exit 0 ;;
    -*) echo "peer-appearance: unknown option $1" >&2; exit 2 ;;
    *) inputs+=("$1"); shift ;;
  esac
done
if [ ${#inputs[@]} -eq 0 ]; then
  inputs=(/usr/share/assimp/models/OBJ/spider.obj
          /usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb
          /usr/share/assimp/models/glTF2/ClearCoat-glTF/ClearCoatTest.gltf)
fi

bake="$build/bin/ngi-bake"
eval_tool="$build/bin/ngi-eval"
for tool in "$bake" "$eval_tool"; do
  [ -x "$tool" ] || { echo "peer-appearance: $tool is missing (build ngi-bake and ngi-eval first)" >&2; exit 1; }
done
command -v cwebp >/dev/null || { echo "peer-appearance: needs cwebp (Debian package webp)" >&2; exit 1; }
command -v npm >/dev/null || { echo "peer-appearance: needs npm to install gltfpack" >&2; exit 1; }
cache="${XDG_CACHE_HOME:-$HOME/.cache}/ngi/gltfpack"
gltfpack="$cache/node_modules/.bin/gltfpack"
if [ ! -x "$gltfpack" ]; then
  mkdir -p "$cache"
  npm install --silent --prefix "$cache" gltfpack@1.3.0 >&2
fi
webp="$root/tools/peer-appearance-webp.py"
mkdir -p "$out"

# ngi-eval distance --json of a candidate against the input into a file (the script stops
# with the tool's message if it fails).
measure() {  # input candidate json
  if ! "$eval_tool" distance "$1" "$2" --samples "$samples" --json >"$3" 2>"$3.err"; then
    echo "peer-appearance: ngi-eval distance $1 $2 failed: $(cat "$3.err")" >&2
    exit 1
  fi
}

# CD HD Y Cb Cr and the candidate's triangles from measure's file.
summary() {
  python3 -c '
import json, sys
j = json.load(open(sys.argv[1]))
c = j.get("colour") or {}
f = lambda v: "inf" if v == "inf" else ("-" if v is None else "%.2f" % v)
print("%.4f %.3f %s %s %s %d" % (j["chamfer_x1e-4"], j["hausdorff_x1e-2"], f(c.get("psnr_y")), f(c.get("psnr_cb")),
                                 f(c.get("psnr_cr")), j["candidate"]["triangles"]))' "$1"
}

# gltfpack at ratio R, then the images as WebP: prints the packed file's bytes.
# Quality "orig": the input's own images, as gltfpack embeds them.
# A ratio that leaves no triangle does not fit (prints 999999999).
pack() {  # input R scale quality output
  local log
  log=$("$gltfpack" -i "$1" -o "$5.geo.glb" -cc -si "$2" -se 1 -v 2>&1) || { echo 999999999; return; }
  if ! grep -q "^output: .*mesh primitives ([1-9][0-9]* triangles" <<<"$log"; then echo 999999999; return; fi
  if [ "$4" = orig ]; then
    cp "$5.geo.glb" "$5"
    stat -c %s "$5"
  else
    python3 "$webp" "$5.geo.glb" "$5" "$3" "$4"
  fi
}

items=()
for input in "${inputs[@]}"; do
  name="$(basename "${input%.*}")"
  IFS=',' read -r -a list <<<"$budgets"
  for budget in "${list[@]}"; do
    base="$out/$name.$budget"
    # ngi: the baked asset and its drawn mesh at LoD 0.
    if [ ! -s "$base.ngi" ]; then
      nice "$bake" "$input" -o "$base.ngi" --target-bytes "$budget" >"$base.bake.log" 2>&1 ||
        echo "peer-appearance: ngi-bake failed on $input (see $base.bake.log)" >&2
    fi
    if [ -s "$base.ngi" ]; then
      "$eval_tool" mesh "$base.ngi" --lod 0 -o "$base.ngi.glb" >"$base.mesh.log" 2>&1
      measure "$input" "$base.ngi.glb" "$base.ngi.json"
      rm -f "$base.ngi.glb" "$base.ngi.json.err"  # millions of triangles: measured, not kept
    fi

    # gltfpack: the largest R within the budget for each texture setting.
    : >"$base.peer.tsv"
    for setting in 1:orig 1:85 1:50 0.5:85 0.5:50 0.25:85 0.25:50 0.125:85 0.125:50 0.0625:85 0.0625:50; do
      scale=${setting%:*} quality=${setting#*:}
      {
        packed="$base.peer.s$scale.q$quality.glb"
        lo=0; hi=1
        if [ "$(pack "$input" 1 "$scale" "$quality" "$packed")" -gt "$budget" ]; then
          for _ in 1 2 3 4 5 6 7 8 9 10; do
            mid=$(python3 -c "print(($lo + $hi) / 2)")
            if [ "$(pack "$input" "$mid" "$scale" "$quality" "$packed")" -le "$budget" ]; then lo=$mid; else hi=$mid; fi
          done
          [ "$lo" != 0 ] || continue  # nothing with a triangle fits
          hi=$lo
        fi
        bytes=$(pack "$input" "$hi" "$scale" "$quality" "$packed")
        "$gltfpack" -i "$packed" -o "$packed.decoded.glb" -noq >/dev/null 2>&1 ||
          { echo "peer-appearance: gltfpack could not decode $packed" >&2; exit 1; }
        measure "$input" "$packed.decoded.glb" "$packed.json"
        read -r cd hd y cb cr triangles < <(summary "$packed.json")
        printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$hi" "$scale" "$quality" "$bytes" "$triangles" "$cd" "$hd" "$y" "$cb" "$cr" >>"$base.peer.tsv"
        rm -f "$packed.geo.glb" "$packed.decoded.glb" "$packed.json" "$packed.json.err"
      }
    done
    items+=("$name:$budget")
  done
done

python3 "$root/tools/peer-appearance-table.py" "$out" "${items[@]}"
