#!/usr/bin/env bash
# Installs the Debian 12 packages pcl_icf needs to build, test, benchmark and render, when any
# is missing. Idempotent and non-interactive; needs root (or sudo) only when it installs.
set -euo pipefail

PACKAGES=(
  build-essential cmake ninja-build pkg-config
  libpcl-dev libopenmpi-dev openmpi-bin libeigen3-dev libembree-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  clang clang-format libclang-rt-14-dev libomp-14-dev lld
  xvfb xauth gnuplot-nox
  nlohmann-json3-dev zlib1g-dev libpng-dev
  python3-dev python3-pybind11 python3-numpy python3-pytest
  libopen3d-dev libopencv-dev libopencv-contrib-dev
)

missing=()
for p in "${PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#PACKAGES[@]} Debian packages present"
  exit 0
fi
echo "setup: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "setup: run as root to install: ${missing[*]}" >&2; exit 1; }
  SUDO=sudo
fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
