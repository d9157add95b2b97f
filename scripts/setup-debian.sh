#!/usr/bin/env bash
# Installs the Debian 12 packages GeoStation needs to build, test and run,
# skipping those already installed. Needs root (or sudo).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libceres-dev libopencv-dev libgdal-dev libproj-dev libgeos-dev nlohmann-json3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  qtbase5-dev qttools5-dev qttools5-dev-tools libqt5svg5-dev
  libqgis-dev qgis qgis-providers python3-qgis
  gdal-bin python3-gdal python3-numpy python3-jsonschema python3-pyqt5
  python3-distributed python3-dask
  xvfb xauth
  opencv-doc colmap
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "Installing ${#missing[@]} Debian packages: ${missing[*]}"
sudo=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo > /dev/null || { echo "setup-debian.sh: run as root (or install sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" > /dev/null
