#!/usr/bin/env bash
# Blender check (not run in CI: Blender is large): installs Blender from Debian when it is missing, bakes the bunny
# scene with --up z, imports the .vdb into Blender headless, meshes it with the Volume to Mesh modifier at threshold
# 0 (and 0.1, Blender's default, for comparison) and checks that the mesh stands upright within half a voxel of the
# scene's bounds. docs/blender.md records a run.
#
#   scripts/blender_check.sh [PICTURE.png]    (RTSDF=path/to/rtsdf, RES=voxels across; defaults: build/, 64)
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
rtsdf=${RTSDF:-$root/build/apps/rtsdf/rtsdf}
res=${RES:-64}
picture=${1:-}
[[ -z "$picture" || "$picture" = /* ]] || picture="$PWD/$picture"

if ! command -v blender >/dev/null; then
  echo "installing Blender from Debian (apt-get install blender)"
  apt-get update -qq
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends blender
fi
[[ -x "$rtsdf" ]] || { echo "no rtsdf at $rtsdf: build it first (or set RTSDF)" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The bunny scene is data/meshes/bunny.obj scaled by 0.2 (data/scenes/bunny.json); its bounds are the mesh's times
# 0.2, turned Z-up in the check.
"$rtsdf" bake "$root/data/scenes/bunny.json" -o "$work/bunny.vdb" --res "$res" --up z
blender -b --factory-startup --python "$root/scripts/blender_check.py" -- \
  "$work/bunny.vdb" "$root/data/meshes/bunny.obj" 0.2 ${picture:+"$picture"}
