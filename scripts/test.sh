#!/usr/bin/env bash
# Set everything up, build, and run every test through ctest (Vulkan validation on, lavapipe on CPU-only
# machines). Usage: scripts/test.sh [Release|Sanitize] [CTEST ARGS...]   (e.g. -E REGEX to leave tests out)
set -euo pipefail
cd "$(dirname "$0")/.."
type="${1:-Release}"
shift $(( $# > 0 ? 1 : 0 ))
dir=build
[ "$type" = Release ] || dir="build-$(echo "$type" | tr '[:upper:]' '[:lower:]')"
./scripts/build.sh "$type"
cd "$dir"
ctest --output-on-failure -j "$(nproc)" "$@"
