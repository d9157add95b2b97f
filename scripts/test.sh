#!/usr/bin/env bash
# Installs missing Debian packages, builds, and runs every test through CTest:
# core (GoogleTest), provider (QtTest) and end-to-end (qgis_process.bin, and
# QGIS desktop under xvfb-run). Test artifacts (screenshots) go to
# build/test-artifacts/. Then the core tests again, built with AddressSanitizer
# and UndefinedBehaviorSanitizer (scripts/sanitize.sh; about 13 minutes on two
# cores): any finding fails the run.
#
#   scripts/test.sh [--no-sanitize] [ctest options]
set -euo pipefail
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${GEOSTATION_BUILD_DIR:-$source_dir/build}"
sanitize=1
if [ "${1:-}" = "--no-sanitize" ]; then
  sanitize=0
  shift
fi

"$source_dir/scripts/setup-debian.sh"
mkdir -p "$build_dir"
"$source_dir/scripts/build.sh"
cd "$build_dir"
ctest -j"$(nproc)" --output-on-failure --timeout 900 "$@"
if [ "$sanitize" = 1 ]; then
  "$source_dir/scripts/sanitize.sh"
fi
