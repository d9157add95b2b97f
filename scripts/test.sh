#!/usr/bin/env bash
# Installs missing Debian packages, builds, and runs every test through CTest:
# core (GoogleTest), provider (QtTest) and end-to-end (qgis_process.bin, and
# QGIS desktop under xvfb-run). Test artifacts (screenshots) go to
# build/test-artifacts/.
set -euo pipefail
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${GEOSTATION_BUILD_DIR:-$source_dir/build}"

"$source_dir/scripts/setup-debian.sh"
mkdir -p "$build_dir"
"$source_dir/scripts/build.sh"
cd "$build_dir"
ctest --output-on-failure --timeout 900 "$@"
