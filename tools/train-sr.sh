#!/usr/bin/env bash
# Reproduces a shipped super-resolution network assets/sr-xFACTOR.ngiw:
#   bash tools/train-sr.sh [FACTOR] [OUT.ngiw]      FACTOR 2, 4, 8 (default), 16 or 32
# 1. bakes the TRAINING set of DESIGN.md with `ngi-bake --export-full data/train --no-split`
#    (full 1025^2 position + normal images, one chart per mesh as the shipped networks were
#    trained; couplingdown is left out: its map is broken, see the bake notes) and the development set into data/devfull (validation display only: it
#    never feeds the optimizer); images already there are reused;
# 2. trains the default network of that factor (HermiteSkip, ngi/nn/architecture.h) for a
#    fixed schedule, seed 1, 2 threads: `ngi-train --scale FACTOR --steps 4000 --lr 2e-4`.
#    x4 trains on decoded inputs (--decoded-steps: the stored level coded + decoded by the
#    asset codec, so the network also removes coding noise) at the steps and tangent scale
#    ngi-bake --target-bytes picks for a 257^2 stored level (assets/README.md); x8 keeps the
#    plain-input command that made today's sr-x8.ngiw (bit for bit). Patches keep x8's
#    289^2 fine window and 193^2 loss window (MS-SSIM needs >= 176): x4 61 coarse samples,
#    x16 19 with 3 of context, x32 11 with 2 (a 193^2 loss window). x2 (the 513^2 level, which --target-bytes picks on about 40%
#    of data/meshes at 16 KB and from 32 KB up) keeps a 177^2 loss window (101 coarse
#    samples) and halves the features (F16): at F32 its heavy work on the 4x larger stored
#    grid would cost 16,065 multiply-adds per output sample, beyond the weights file's limit
#    (8192); F16 costs about x4's. Its decoded steps 16-256, tangent scale 2, are what the
#    rate control picks for 513^2 in the 16 KB batch of data/meshes (median step 62).
# Wall time on the 2-core development machine: ~19-30 min for the training of x8, x16 and x32
# (x16: 25 min 14 s; x32: 29 min 21 s), ~1.5 h for x4's first stage (plus ~6 min per 20 meshes to bake if
# data/train is empty). knot2 bakes as two components, so data/train holds 21 images.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/bin"
factor="${1:-8}"
extra=()
case "$factor" in
  2)  decoded=(--patch 101 --decoded-steps 16,32,64,128,256 --decoded-tangent-scale 2 --val-decoded-step 64); extra=(--features 16) ;;
  4)  decoded=(--patch 61 --decoded-steps 4,8,16,32,64 --decoded-tangent-scale 8) ;;
  8)  decoded=() ;;
  16) decoded=(--patch 19 --context 3 --decoded-steps 1,64,256,1024 --decoded-tangent-scale 2) ;;
  32) decoded=(--patch 11 --context 2 --decoded-steps 256,512,1024,2048 --decoded-tangent-scale 2 --val-decoded-step 1024) ;;
  *)  echo "train-sr.sh: factor '$factor' is not 2, 4, 8, 16 or 32" >&2; exit 2 ;;
esac
out="${2:-$root/assets/sr-x$factor.ngiw}"
[ -x "$bin/ngi-train" ] || bash "$root/tools/build.sh"
meshes="$("$root/tools/fetch-data.sh")"
train=(bunny00 camel cow bull bear bear_bis triceratops blobby hand handle retinal ellipe0.003 larger_sphere
       knot2 rotor_small turbine anchor_dense head three_peaks cylinder_locally_refined)
dev=(fandisk elephant knot1 mushroom elk)
bake() {  # bake MESH DIR: NAME_position.png + NAME_normal.png into DIR unless present
  local name="$1" dir="$2"
  mkdir -p "$dir" "$root/data/bake"
  if [ ! -f "$dir/${name}_position.png" ] || [ ! -f "$dir/${name}_normal.png" ]; then
    echo "baking $name -> $dir" >&2
    "$bin/ngi-bake" "$meshes/$name.off" -o "$root/data/bake/$name.ngi" --export-full "$dir" --no-split --quiet >&2
  fi
}
for m in "${train[@]}"; do bake "$m" "$root/data/train"; done
for m in "${dev[@]}"; do bake "$m" "$root/data/devfull"; done
# x4 is trained in two stages: the schedule above into a first network, then a fine-tune of
# it at the steps --target-bytes picks for 257^2 at 16 KB (16-256, between the tangent scales
# 2 and 8 it picks) with the point-to-plane L1 added to the loss (--normal-l1 2), which charges
# what moves the surface rather than what slides samples within it (offline/nn/README.md).
first="$out"
[ "$factor" = 4 ] && first="$root/data/sr-x4-first.ngiw"
"$bin/ngi-train" --data "$root/data/train" --val-data "$root/data/devfull" --scale "$factor" --steps 4000 --lr 2e-4 --seed 1 \
  --threads 2 --val-every 500 --checkpoint-dir "$root/data/sr-x$factor-checkpoints" --checkpoint-every 500 \
  ${decoded[@]+"${decoded[@]}"} ${extra[@]+"${extra[@]}"} --name "ngi-sr-x$factor" --export "$first"
if [ "$factor" = 4 ]; then
  "$bin/ngi-train" --data "$root/data/train" --val-data "$root/data/devfull" --scale 4 --steps 2000 --lr 1e-4 --seed 1 \
    --threads 2 --val-every 500 --checkpoint-dir "$root/data/sr-x4-finetune-checkpoints" --checkpoint-every 250 \
    --patch 61 --decoded-steps 16,32,64,128,256 --decoded-tangent-scale 4 --val-decoded-step 64 --normal-l1 2 \
    --init "$first" --name ngi-sr-x4 --export "$out"
fi
