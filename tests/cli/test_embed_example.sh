#!/usr/bin/env bash
# Package.EmbedExampleBuildsAgainstTheInstall: `cmake --install` this build into a temporary prefix, configure and
# build examples/embed against it with find_package(rtsdf), run it on the default scene, and check that its .vdb
# equals the command line's bake of the same frame and settings, voxel for voxel; with PYTHON given (the build
# has the Python module), the installed module imports from the prefix too.
# Usage: test_embed_example.sh SOURCE_DIR BUILD_DIR CXX_COMPILER "CXX_FLAGS" "LINKER_FLAGS" [PYTHON]
set -euo pipefail
source_dir="$1" build_dir="$2" cxx="$3" cxx_flags="$4" link_flags="$5" python="${6:-}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

cmake --install "$build_dir" --prefix "$work/prefix" > "$work/install.log"
[ -f "$work/prefix/lib/cmake/rtsdf/rtsdfConfig.cmake" ] || fail "no package config installed"
[ -f "$work/prefix/include/rtsdf/sdf/SdfPipeline.h" ] || fail "no public headers installed"
# The example's own build: only the installed prefix, no path into the source or build tree.
cmake -S "$source_dir/examples/embed" -B "$work/build" -DCMAKE_PREFIX_PATH="$work/prefix" \
      -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_CXX_FLAGS="$cxx_flags" -DCMAKE_EXE_LINKER_FLAGS="$link_flags"
cmake --build "$work/build" -j 2
if grep -q "$build_dir/lib\|$source_dir/lib" "$work/build/CMakeCache.txt" "$work/build"/CMakeFiles/*/flags.make \
     2>/dev/null; then
  fail "the example's build reaches into the rtsdf tree"
fi

scene="$source_dir/data/scenes/default.json"
"$work/build/embed" "$scene" "$work/embed" 3 | tee "$work/embed.log"
[ -s "$work/embed.vdb" ] || fail "embed wrote no .vdb"
[ -s "$work/embed.png" ] || fail "embed wrote no .png"
grep -q "^frame 3: " "$work/embed.log" || fail "embed did not run 3 frames"
# The same frame (the third at 30 fps) and settings from the command line: the same field.
rtsdf="$work/prefix/bin/rtsdf"
"$rtsdf" -q bake "$scene" --method rtsdf --coarse 64 --fine 128 --refine closest --rays 0 --time 0.0666667 \
         -o "$work/bake.vdb"
"$rtsdf" compare "$work/embed.vdb" "$work/bake.vdb" | tee "$work/compare.log"
grep -q "(0 only in A, 0 only in B)" "$work/compare.log" || fail "the active voxels differ from the bake's"
grep -q "max 0.0000 voxels" "$work/compare.log" || fail "the values differ from the bake's"
if [ -n "$python" ]; then
  triangles="$(cd "$work" && PYTHONPATH="$work/prefix/lib/python3/dist-packages" "$python" -c \
    "import rtsdf; print(rtsdf.__file__.startswith('$work/prefix'), rtsdf.load_scene('$scene').triangles)")"
  [ "$triangles" = "True 4882" ] || fail "the installed Python module: $triangles"
fi
echo "PASS"
