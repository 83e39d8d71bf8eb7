#!/usr/bin/env bash
# Bundle.RunsOutsideTheBuildTree: scripts/bundle.sh packs this build; the tarball, unpacked in a temporary
# folder, must resolve every library outside the C and C++ runtimes from its own lib/, and run `rtsdf info`
# and a small GPU bake under `env -i` from that folder (no build tree, no source tree, no LD_LIBRARY_PATH).
# Usage: test_bundle.sh SOURCE_DIR BUILD_DIR
set -euo pipefail
source_dir="$1" build_dir="$2"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

"$source_dir/scripts/bundle.sh" --build-dir "$build_dir" -o "$work/rtsdf.tar.gz"
mkdir "$work/unpacked"
tar -C "$work/unpacked" -xzf "$work/rtsdf.tar.gz"
bundle="$(realpath "$work"/unpacked/rtsdf-*)"
[ -x "$bundle/bin/rtsdf" ] || fail "the tarball has no rtsdf-*/bin/rtsdf"

# What the loader would resolve, with nothing in the environment: only the runtimes may come from the system
# (glibc's libraries, which bundle.sh leaves to the machine, libstdc++ and libgcc_s).
runtimes='^(linux-vdso|ld-linux|libc|libm|libpthread|libdl|librt|libresolv|libutil|libstdc\+\+|libgcc_s)\.so'
resolved="$(cd "$work" && env -i PATH=/usr/bin:/bin ldd "$bundle/bin/rtsdf")"
echo "$resolved"
while read -r soname arrow path _; do
  [ "$arrow" = "=>" ] || continue
  [[ "$soname" =~ $runtimes ]] && continue
  path="$(realpath "$path")"
  [[ "$path" == "$bundle/lib/"* ]] || fail "$soname resolves to $path, not into the bundle's lib/"
done <<< "$resolved"
readelf -d "$bundle/bin/rtsdf" | grep -q 'R.*PATH.*\[\$ORIGIN/\.\./lib\]' || fail "bin/rtsdf's search path is not \$ORIGIN/../lib"
if readelf -d "$bundle/bin/rtsdf" | grep -q "$build_dir"; then fail "bin/rtsdf names the build tree"; fi

# Run it as a stranger would: a bare environment, from the temporary folder. What the test harness sets for
# the sanitizers and the validation layer passes through (validation errors fail the bake).
pass=(PATH=/usr/bin:/bin HOME="$work")
for v in RTSDF_VALIDATION RTSDF_SYNC_VALIDATION ASAN_OPTIONS LSAN_OPTIONS UBSAN_OPTIONS; do
  [ -z "${!v:-}" ] || pass+=("$v=${!v}")
done
cd "$work"
env -i "${pass[@]}" "$bundle/bin/rtsdf" info | tee info.txt
grep -q "Vulkan devices" info.txt || fail "rtsdf info listed no Vulkan devices"
env -i "${pass[@]}" "$bundle/bin/rtsdf" bake "$bundle/data/scenes/teapot.json" -m rtsdf --coarse 32 --fine 64 \
  --frames 2 -o teapot.vdb
[ -s teapot.vdb ] || fail "the bake wrote no teapot.vdb"
echo "PASS: the bundle runs outside the build tree"
