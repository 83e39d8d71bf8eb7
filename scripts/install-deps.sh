#!/usr/bin/env bash
# Installs the Debian 12 packages rtsdf needs to build, test and run. Idempotent: packages that are
# already installed are skipped, and nothing is done when all are present.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libopenvdb-dev libopenvdb-tools python3-openvdb libboost-iostreams-dev libblosc-dev
  libembree-dev libtbb-dev libopenexr-dev libimath-dev libpng-dev python3-imath libglm-dev
  libvulkan-dev mesa-vulkan-drivers glslc vulkan-validationlayers vulkan-tools
  libassimp-dev libcgal-dev nlohmann-json3-dev libcli11-dev libspdlog-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3-dev pybind11-dev python3-numpy python3-pytest python3-distributed
  libglfw3-dev libstb-dev xvfb xauth
  gnuplot-nox
  clang libclang-rt-14-dev
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q 'install ok installed'; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${#missing[@]} package(s): ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
