#!/usr/bin/env bash
# Builds the CAD and game-like corpus of DESIGN.md ("Data") from Debian packages into
# ./data/cad (never committed). Idempotent: an existing data/cad is kept as it is (delete it
# to rebuild).
#   - openscad: every example under /usr/share/openscad/examples rendered to STL
#     (openscad-CATEGORY-NAME.stl); an example that fails or takes longer than 60 s is skipped.
#   - assimp-testmodels: every OBJ/OFF/PLY/STL/glTF/GLB model (assimp-DIR-NAME.EXT), the
#     files beside an OBJ or .gltf (MTL, buffers, textures) copied next to it under their own names; a
#     model whose side file clashes with another model's side file of different contents is
#     skipped. The package's deliberately broken inputs (invalid/, wrongTypes/, ...) are kept:
#     they check that the reader refuses them cleanly.
# ngi-bake --batch data/cad bakes the lot (the directory is flat: the batch does not recurse).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
out="$root/data/cad"
if [ -d "$out" ]; then
  echo "$out"
  exit 0
fi

need=()
command -v openscad > /dev/null || need+=(openscad)
dpkg -s assimp-testmodels > /dev/null 2>&1 || need+=(assimp-testmodels)
if [ "${#need[@]}" -gt 0 ]; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends "${need[@]}" >&2
fi

staging="$(mktemp -d "$root/data/.cad.XXXXXX")"
trap 'rm -rf "$staging"' EXIT

# OpenSCAD's examples. Rendered from their own directory (some import files beside them).
scad_root=/usr/share/openscad/examples
rendered=0 skipped=0
while IFS= read -r -d '' scad; do
  rel="${scad#"$scad_root"/}"
  name="openscad-$(echo "${rel%.scad}" | tr '/ ' '--').stl"
  if (cd "$(dirname "$scad")" && timeout 60 openscad -q -o "$staging/$name" "$scad") > /dev/null 2>&1 \
     && [ -s "$staging/$name" ]; then
    rendered=$((rendered + 1))
  else
    rm -f "$staging/$name"
    skipped=$((skipped + 1))
    echo "fetch-cad-data: skipped $rel (openscad failed, timed out or wrote no solid)" >&2
  fi
done < <(find "$scad_root" -name '*.scad' -print0 | sort -z)
echo "fetch-cad-data: $rendered OpenSCAD examples rendered, $skipped skipped" >&2

# assimp's test models.
models="$(dpkg -L assimp-testmodels | grep -m1 -E '/models$' || true)"
[ -n "$models" ] || models=/usr/share/assimp/models
copied=0 clashed=0
while IFS= read -r -d '' mesh; do
  rel="${mesh#"$models"/}"
  dir="$(dirname "$mesh")"
  name="assimp-$(echo "$rel" | tr '/ ' '--')"
  ok=1
  # Side files (OBJ and .gltf only; the other formats hold everything): everything beside the
  # model that is not itself a mesh the corpus lists.
  case "${mesh,,}" in *.obj|*.gltf) sides="$dir" ;; *) sides="" ;; esac
  [ -z "$sides" ] || while IFS= read -r -d '' side; do
    target="$staging/${side#"$dir"/}"
    if [ -e "$target" ] && ! cmp -s "$side" "$target"; then ok=0; break; fi
  done < <(find "$sides" -type f ! -iregex '.*\.\(obj\|off\|ply\|stl\|gltf\|glb\)$' -print0)
  if [ "$ok" -eq 0 ]; then
    clashed=$((clashed + 1))
    echo "fetch-cad-data: skipped $rel (a side file clashes with another model's)" >&2
    continue
  fi
  [ -z "$sides" ] || while IFS= read -r -d '' side; do
    target="$staging/${side#"$dir"/}"
    mkdir -p "$(dirname "$target")"
    [ -e "$target" ] || cp "$side" "$target"
  done < <(find "$sides" -type f ! -iregex '.*\.\(obj\|off\|ply\|stl\|gltf\|glb\)$' -print0)
  cp "$mesh" "$staging/$name"
  copied=$((copied + 1))
done < <(find "$models" -type f -iregex '.*\.\(obj\|off\|ply\|stl\|gltf\|glb\)$' -print0 | sort -z)
echo "fetch-cad-data: $copied assimp models copied, $clashed skipped" >&2

mkdir -p "$root/data"
mv "$staging" "$out"
trap - EXIT
echo "$out"
