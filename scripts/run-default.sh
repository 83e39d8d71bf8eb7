#!/usr/bin/env bash
# The main job: set everything up, then bake the exact SDF of the bundled default scene to out/default.vdb
# (a level set named "surface" plus a "density" fog grid for Blender) and print a summary.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh Release
mkdir -p out
./build/apps/rtsdf/rtsdf bake data/scenes/default.json --method exact --res 128 --band 0.1 --fog -o out/default.vdb
