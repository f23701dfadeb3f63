#!/usr/bin/env bash
# Unpacks the real meshes of DESIGN.md ("Data") from Debian's libcgal-demo package into
# ./data (never committed). Idempotent. Meshes end up in data/meshes/*.off.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if [ ! -f /usr/share/doc/libcgal-dev/data.tar.gz ]; then
  sudo=""; [ "$(id -u)" -ne 0 ] && sudo="sudo"
  $sudo apt-get install -y --no-install-recommends libcgal-demo >&2
fi
if [ ! -d "$root/data/meshes" ]; then
  mkdir -p "$root/data"
  tar xzf /usr/share/doc/libcgal-dev/data.tar.gz -C "$root" data/meshes
fi
echo "$root/data/meshes"
