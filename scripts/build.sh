#!/usr/bin/env bash
# Install the Debian packages (if missing), then configure and build rtsdf.
# Usage: scripts/build.sh [Release|Debug|RelWithDebInfo|Sanitize] [TARGET...]
#   build folder: build/ or build-<type>/; every target unless some are named. Sanitize is built with clang: the
#   same build holds the test suite and the libFuzzer targets (scripts/fuzz.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
type="${1:-Release}"
shift $(( $# > 0 ? 1 : 0 ))
dir=build
[ "$type" = Release ] || dir="build-$(echo "$type" | tr '[:upper:]' '[:lower:]')"
./scripts/install-deps.sh
if [ "$type" = Sanitize ]; then
  # The compiler is chosen when a build folder is first configured; one configured with another stays so.
  if [ -f "$dir/CMakeCache.txt" ] && ! grep -q '^CMAKE_CXX_COMPILER:.*clang' "$dir/CMakeCache.txt"; then
    echo "scripts/build.sh: $dir was configured with another compiler than clang; remove $dir and run again" >&2
    exit 2
  fi
  export CC=clang CXX=clang++
fi
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE="$type" >/dev/null
ninja -C "$dir" "$@"
if [ $# -eq 0 ]; then echo "built: $dir/apps/rtsdf/rtsdf"; else echo "built in $dir: $*"; fi
