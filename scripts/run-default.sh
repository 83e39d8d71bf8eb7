#!/usr/bin/env bash
# The main job: set everything up, then bake the exact SDF of the bundled default scene to out/default.vdb
# (a level set named "surface" plus a "density" fog grid for Blender) and render the scene's soft shadows
# through the RTSDF pipeline (GPU: lavapipe without a GPU) to out/default.exr and out/default.png, with the
# image error against the ray-traced truth.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/build.sh Release
mkdir -p out
./build/apps/rtsdf/rtsdf bake data/scenes/default.json --fog -o out/default.vdb
./build/apps/rtsdf/rtsdf render data/scenes/default.json --shadows sdf --frames 4 --compare -o out/default.exr
