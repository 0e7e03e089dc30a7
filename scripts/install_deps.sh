#!/usr/bin/env bash
# Install what the project needs from Debian 12, only if it is missing.
# Idempotent: a second run installs nothing.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libhdf5-dev libgsl-dev libzip-dev libgtest-dev libsodium-dev libxml2-dev
  libmuparser-dev
  libopenmpi-dev openmpi-bin libmetis-dev
  libxml2-utils unzip hdf5-tools gmsh
  python3 python3-h5py python3-matplotlib python3-numpy python3-pandas python3-scipy
  g++-mingw-w64-x86-64-posix wine wine64
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages present"
  exit 0
fi
echo "install_deps: installing ${missing[*]}"
sudo=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install_deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo=sudo
fi
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
