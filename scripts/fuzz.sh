#!/usr/bin/env bash
# Build the libFuzzer targets (the Sanitize build, clang: ASan + UBSan; after CI's sanitizer run they are built
# already) and run each on a seed corpus made from data/, after replaying every saved crash input in
# fuzz/regressions/<target>/. Any crash, leak, sanitizer report, timeout or memory blow-up fails the script and
# leaves the input under build-sanitize/fuzz-artifacts/: add it to
# fuzz/regressions/<target>/ (and, for a CLI-reachable case, a row to tests/cli/bad_inputs.json) with the fix.
# Usage: scripts/fuzz.sh                  CI: a fixed seed and at most a fixed number of inputs per target, each
#                                         target capped in time (seconds below: about three minutes in all on
#                                         2 cores; runs still differ a little: coverage feedback depends on
#                                         addresses)
#        scripts/fuzz.sh --explore SECONDS  a random seed for SECONDS per target: to find new inputs
# Seeds: fuzz/seeds/<target>/ (files rtsdf wrote: .vdb with zip and blosc, half floats; binary PLY/STL, GLB,
# glTF; scenes of built-in meshes; command lines) and seeds made here from data/.
set -euo pipefail
cd "$(dirname "$0")/.."
explore=""
if [ "${1:-}" = "--explore" ]; then explore="${2:?--explore needs seconds per target}"; fi
# Inputs per target in CI, and the time each may take at most: CI's fuzzing stays within a few minutes whatever
# the machine. Most targets end at their time (2 cores, 2026-11-27, inputs in its seconds: scene 6800, mesh 4500,
# .vdb 85000, binary meshes, glTF and scene geometry all of theirs, compare 4900, command line 2200).
targets=(fuzz_scene_json fuzz_mesh fuzz_vdb fuzz_mesh_binary fuzz_gltf fuzz_scene_geometry fuzz_compare fuzz_cli)
declare -A runs=([fuzz_scene_json]=100000 [fuzz_mesh]=12000 [fuzz_vdb]=2000000 [fuzz_mesh_binary]=20000
                 [fuzz_gltf]=20000 [fuzz_scene_geometry]=50000 [fuzz_compare]=20000 [fuzz_cli]=50000)
declare -A seconds=([fuzz_scene_json]=25 [fuzz_mesh]=25 [fuzz_vdb]=20 [fuzz_mesh_binary]=20 [fuzz_gltf]=20
                    [fuzz_scene_geometry]=20 [fuzz_compare]=25 [fuzz_cli]=20)
./scripts/build.sh Sanitize "${targets[@]}"

build=build-sanitize
seeds=$build/fuzz-seeds
artifacts=$build/fuzz-artifacts
logs=$build/fuzz-logs
rm -rf "$seeds" "$artifacts" "$logs"
mkdir -p "$artifacts" "$logs"
for target in "${targets[@]}"; do
  mkdir -p "$seeds/$target"
  if [ -d "fuzz/seeds/$target" ]; then cp -r "fuzz/seeds/$target/." "$seeds/$target/"; fi
done
cp data/scenes/*.json "$seeds/fuzz_scene_json/"
# Mesh seeds: the first byte picks the format (0 obj, 1 ply, 2 stl, 3 off), as fuzz/fuzz_mesh.cpp reads it.
{ printf '\0'; head -c 4000 data/meshes/teapot.obj; } > "$seeds/fuzz_mesh/teapot-head.obj"
{ printf '\0'; head -c 4000 data/meshes/bunny.obj; } > "$seeds/fuzz_mesh/bunny-head.obj"
printf '\1ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' \
  > "$seeds/fuzz_mesh/tri.ply"
printf '\2solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid t\n' \
  > "$seeds/fuzz_mesh/tri.stl"
printf '\3OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n' > "$seeds/fuzz_mesh/tet.off"
/usr/bin/python3 - "$seeds/fuzz_vdb" <<'PY'
import sys, pyopenvdb as vdb
g = vdb.createLevelSetSphere(radius=1.0, center=(0, 0, 0), voxelSize=0.25, halfWidth=2.0)
g.name = "surface"
vdb.write(sys.argv[1] + "/sphere.vdb", grids=[g])
PY
# Two-file compare: the first 4 bytes say where the first file ends (fuzz/fuzz_compare.cpp).
pair() { /usr/bin/python3 -c 'import sys,struct; a=open(sys.argv[1],"rb").read(); b=open(sys.argv[2],"rb").read()
open(sys.argv[3],"wb").write(struct.pack("<I",len(a))+a+b)' "$@"; }
# The bunny as rtsdf bake writes it (fuzz/seeds/fuzz_vdb: zip + half, blosc), paired for compare.
pair fuzz/seeds/fuzz_vdb/bunny-zip-half.vdb fuzz/seeds/fuzz_vdb/bunny-blosc.vdb "$seeds/fuzz_compare/zip-half-blosc"
pair fuzz/seeds/fuzz_vdb/bunny-blosc.vdb "$seeds/fuzz_vdb/sphere.vdb" "$seeds/fuzz_compare/bunny-sphere"
pair "$seeds/fuzz_vdb/sphere.vdb" "$seeds/fuzz_vdb/sphere.vdb" "$seeds/fuzz_compare/sphere-sphere"

export LSAN_OPTIONS="suppressions=$PWD/fuzz/lsan.supp:print_suppressions=0"
status=0
for target in "${targets[@]}"; do
  regressions="fuzz/regressions/$target"
  mkdir -p "$regressions"
  bound=(-seed=1 -runs="${runs[$target]}" -max_total_time="${seconds[$target]}")
  if [ -n "$explore" ]; then bound=(-max_total_time="$explore"); fi
  echo "== $target: ${bound[*]} (seeds: $(ls "$seeds/$target" | wc -l), regressions: $(ls "$regressions" | wc -l))"
  # Regressions are replayed one by one (each must end cleanly), then the fuzzer starts from the seeds.
  if [ -n "$(ls "$regressions")" ] && ! "$build/fuzz/$target" "$regressions"/* -timeout=10 -rss_limit_mb=2048 \
       -malloc_limit_mb=2048 2> "$logs/$target-replay.log"; then
    tail -40 "$logs/$target-replay.log"
    status=1
  fi
  if ! "$build/fuzz/$target" "$seeds/$target" "${bound[@]}" -max_len=65536 \
       -timeout=10 -rss_limit_mb=2048 -malloc_limit_mb=2048 -artifact_prefix="$artifacts/$target-" \
       -print_final_stats=1 2> "$logs/$target.log"; then
    tail -40 "$logs/$target.log"
    status=1
  fi
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$logs/$target.log" | tr '\n' ' '; echo
done
ls "$artifacts"
exit $status
