#!/usr/bin/env bash
# Pack the command line into a relocatable tarball that runs on another Linux x86-64 machine without the Debian
# packages: bin/rtsdf (search path $ORIGIN/../lib), lib/ with every shared library it needs except the C and C++
# runtimes (glibc, libstdc++, libgcc_s: every machine with a Vulkan driver has them, and a bundled older
# libstdc++ would shadow the one the machine's driver was built against), the bundled scenes and meshes, and a
# README naming the glibc and libstdc++ versions the binary needs. The Vulkan driver is the machine's own; the
# Vulkan loader (libvulkan.so.1) is bundled, since a machine with only a driver may lack it.
# Usage: scripts/bundle.sh [--build-dir DIR] [-o FILE.tar.gz]
#   --build-dir DIR  a configured and built tree (default: build; scripts/build.sh makes it)
#   -o FILE          the tarball (default: DIR/rtsdf-VERSION-linux-x86_64.tar.gz); written whole or not at all
# On the other machine: tar xzf FILE && rtsdf-*/bin/rtsdf info
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="$root/build"
output=""
while [ $# -gt 0 ]; do
  case "$1" in
    --build-dir) build="$(cd "${2:?--build-dir needs a folder}" && pwd)"; shift 2 ;;
    -o|--output) output="${2:?-o needs a file}"; shift 2 ;;
    -h|--help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "bundle.sh: unknown argument '$1' (see --help)" >&2; exit 2 ;;
  esac
done
binary="$build/apps/rtsdf/rtsdf"
[ -x "$binary" ] || { echo "bundle.sh: $binary is missing: build it first (scripts/build.sh)" >&2; exit 1; }
version="$("$binary" --version | awk '{print $NF}')"
name="rtsdf-$version-linux-$(uname -m)"
[ -n "$output" ] || output="$build/$name.tar.gz"

stage="$(mktemp -d)"
partial="$output.partial.$$"
trap 'rm -rf "$stage" "$partial"' EXIT
dest="$stage/$name"
cmake --install "$build" --prefix "$dest" --component runtime >/dev/null

# The libraries the loader resolves for the binary, all the way down, less the C and C++ runtimes.
mkdir -p "$dest/lib"
system='^(linux-vdso|ld-linux|libc|libm|libpthread|libdl|librt|libresolv|libutil|libstdc\+\+|libgcc_s)\.so'
ldd "$dest/bin/rtsdf" | while read -r soname arrow path _; do
  [ "$arrow" = "=>" ] || continue
  [[ "$soname" =~ $system ]] && continue
  [ "$path" != "not" ] || { echo "bundle.sh: $soname not found (ldd $binary)" >&2; exit 1; }
  cp -L "$path" "$dest/lib/$soname"
done
mkdir -p "$dest/data"
cp -r "$root/data/scenes" "$root/data/meshes" "$dest/data/"

# The newest symbol versions of glibc and libstdc++ that anything in the bundle asks for.
newest() { objdump -T "$dest"/bin/rtsdf "$dest"/lib/*.so* | grep -o "$1_[0-9.]*" | sort -uV | tail -1; }
cat > "$dest/README.txt" <<EOF
rtsdf $version ($(git -C "$root" describe --always --dirty 2>/dev/null || echo "unknown commit")), $(uname -m) Linux

  bin/rtsdf info                                      the Vulkan devices this machine offers
  bin/rtsdf bake data/scenes/default.json -m rtsdf -o default.vdb
  bin/rtsdf bench data/scenes/default.json --suite refine -o refine.md

lib/ holds the shared libraries rtsdf needs beyond the machine's own C and C++ runtimes, which must provide
$(newest GLIBC) and $(newest GLIBCXX) or newer. The Vulkan driver is the machine's: if 'rtsdf info' lists
no device, point the loader at the driver's manifest, e.g.
  VK_DRIVER_FILES=/usr/share/vulkan/icd.d/nvidia_icd.json bin/rtsdf info
EOF

mkdir -p "$(dirname "$output")"
tar -C "$stage" -czf "$partial" "$name"
mv "$partial" "$output"
echo "bundle.sh: $output ($(du -h "$output" | cut -f1), $(ls "$dest/lib" | wc -l) libraries)"
