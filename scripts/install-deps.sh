#!/usr/bin/env bash
# Installs every Debian 12 package dsdem needs. Idempotent; fast when all is present.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config git
  libeigen3-dev
  gmsh
  libvtk9-dev
  libyaml-cpp-dev
  libcli11-dev
  nlohmann-json3-dev
  libfmt-dev libspdlog-dev
  libhdf5-dev
  libopenmpi-dev openmpi-bin
  libgtest-dev libgmock-dev googletest
  libbenchmark-dev
  python3 python3-matplotlib python3-numpy python3-meshio
  # dsdem render of a 3D run: VTK offscreen; Debian's VTK draws through X only, so Xvfb when headless
  python3-vtk9 xvfb
  ffmpeg
  clang-14 libclang-rt-14-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
