#!/usr/bin/env bash
# Install the Debian packages (if missing), then configure and build rtsdf.
# Usage: scripts/build.sh [Release|Debug|RelWithDebInfo|Sanitize]   (build folder: build/ or build-<type>/)
set -euo pipefail
cd "$(dirname "$0")/.."
type="${1:-Release}"
dir=build
[ "$type" = Release ] || dir="build-$(echo "$type" | tr '[:upper:]' '[:lower:]')"
./scripts/install-deps.sh
cmake -S . -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE="$type" >/dev/null
ninja -C "$dir"
echo "built: $dir/apps/rtsdf/rtsdf"
