#!/usr/bin/env bash
# The equal-bytes peer's rate-distortion table: for each mesh and budget, the
# meshoptimizer + Draco mesh that fits (ngi-peer-equal-bytes) at qp 10, 12 and 14, and the
# CD (x1e-4) of each against the input (ngi-eval distance); the best qp per budget is marked.
#   bash tools/peer-rd.sh MESH...    (PEER_BUDGETS default 4096,8192,16384,32768,65536)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
bin="$root/build/bin"
budgets="${PEER_BUDGETS:-4096,8192,16384,32768,65536}"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
echo "| mesh | budget | best qp | Draco bytes | triangles | CD x1e-4 (best) | CD qp10 / qp12 / qp14 |"
echo "|---|---|---|---|---|---|---|"
for mesh in "$@"; do
  name="$(basename "${mesh%.*}")"
  "$bin/ngi-peer-equal-bytes" "$mesh" -o "$out" ${budgets//,/ } > "$out/list.txt"
  for budget in ${budgets//,/ }; do
    best=""; all=""
    while read -r b qp bytes tris met file; do
      [ "$b" = "$budget" ] || continue
      cd=$("$bin/ngi-eval" distance "$mesh" "$file" --json | grep -o '"chamfer_x1e-4": *[-0-9.e+]*' | sed 's/.*: *//')
      all="$all${all:+ / }$(printf %.4g "$cd")"
      if [ -z "$best" ] || awk -v a="$cd" -v b="${best%% *}" 'BEGIN{exit !(a<b)}'; then best="$cd $qp $bytes $tris"; fi
    done < "$out/list.txt"
    read -r cd qp bytes tris <<< "$best"
    printf "| %s | %s | %s | %s | %s | %.4g | %s |\n" "$name" "$budget" "$qp" "$bytes" "$tris" "$cd" "$all"
  done
done
