#!/usr/bin/env bash
# Installs the Debian 12 packages GeoStation needs to build, test and run,
# skipping those already installed. Needs root (or sudo).
set -euo pipefail

# --runtime (scripts/demo.sh): only what building and running GeoStation needs; without it also what the
# tests need (GoogleTest, Google Benchmark, COLMAP, OpenCV's sample photos, an X server, the test images)
runtime_only=0
[ "${1:-}" = "--runtime" ] && runtime_only=1
packages=(
  build-essential cmake ninja-build pkg-config git
  libeigen3-dev libceres-dev libopencv-dev libgdal-dev libproj-dev libgeos-dev nlohmann-json3-dev
  qtbase5-dev qttools5-dev qttools5-dev-tools libqt5svg5-dev
  libqgis-dev qgis qgis-providers python3-qgis
  gdal-bin python3-gdal python3-numpy python3-pyqt5 python3-markdown
  python3-distributed python3-dask
)
test_packages=(
  libgtest-dev libgmock-dev libbenchmark-dev python3-jsonschema
  xvfb xauth
  opencv-doc colmap
)
[ "$runtime_only" = 1 ] || packages+=("${test_packages[@]}")

# Real images the tests measure on that Debian ships only inside packages not worth installing whole:
# SP27GTIF.TIF (a 10 m image of Chicago) from r-cran-rgdal, unpacked into testdata/ (no root needed).
fetch_test_images() {
  local testdata
  testdata="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)/testdata"
  [ -f "$testdata/SP27GTIF.TIF" ] && return 0
  mkdir -p "$testdata"
  local tmp
  tmp="$(mktemp -d)"
  if (cd "$tmp" && apt-get download -qq r-cran-rgdal > /dev/null 2>&1) && dpkg-deb -x "$tmp"/r-cran-rgdal_*.deb "$tmp/x"; then
    cp "$tmp/x/usr/lib/R/site-library/rgdal/pictures/SP27GTIF.TIF" "$testdata/"
  else
    echo "setup-debian.sh: could not download r-cran-rgdal for testdata/SP27GTIF.TIF (run apt-get update first); its tests will say so" >&2
  fi
  rm -rf "$tmp"
}

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  [ "$runtime_only" = 1 ] || fetch_test_images
  exit 0
fi

echo "Installing ${#missing[@]} Debian packages: ${missing[*]}"
sudo=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo > /dev/null || { echo "setup-debian.sh: run as root (or install sudo) to install: ${missing[*]}" >&2; exit 1; }
  sudo=(sudo)
fi
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" > /dev/null
[ "$runtime_only" = 1 ] || fetch_test_images
