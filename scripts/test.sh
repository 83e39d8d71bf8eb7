#!/usr/bin/env bash
# Set everything up, build, and run the test suite through ctest (Vulkan validation on, lavapipe on CPU-only
# machines). The long tests (label long, tests/long_tests.cmake: accuracy and quality measured at scale, 8.5 minutes
# on 2 cores) run only when asked for: --long runs them alone, --all runs every test.
# Usage: scripts/test.sh [Release|Sanitize] [--long|--all] [CTEST ARGS...]   (e.g. -E REGEX to leave tests out)
set -euo pipefail
cd "$(dirname "$0")/.."
type=Release
if (( $# > 0 )) && [[ $1 != -* ]]; then type=$1; shift; fi
labels=(-LE long)
case "${1:-}" in
  --long) labels=(-L long); shift ;;
  --all) labels=(); shift ;;
esac
dir=build
[ "$type" = Release ] || dir="build-$(echo "$type" | tr '[:upper:]' '[:lower:]')"
./scripts/build.sh "$type"
cd "$dir"
ctest --output-on-failure -j "$(nproc)" "${labels[@]}" "$@"
