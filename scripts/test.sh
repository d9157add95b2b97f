#!/usr/bin/env bash
# Installs missing Debian packages, builds, and runs every test through CTest:
# core (GoogleTest), provider (QtTest) and end-to-end (qgis_process.bin, and
# QGIS desktop under xvfb-run). Test artifacts (screenshots) go to
# build/test-artifacts/. The core tests run once, built with AddressSanitizer
# and UndefinedBehaviorSanitizer (scripts/sanitize.sh): any finding fails the
# run; the main stage builds and runs only those the sanitizer stage leaves
# out or runs on a shorter scene (label core-optimised; --no-sanitize: every
# test here). The sanitizer build runs at the lowest priority while the main
# tests run, on the processor time they leave (qgis_process and QGIS desktop
# starting, the X server, Dask's scheduler waiting), and its tests after them.
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
# with the sanitizer stage the main build compiles only the core tests it runs (label core-optimised)
GEOSTATION_CORE_TESTS="$([ "$sanitize" = 1 ] && echo optimised || echo all)" "$source_dir/scripts/build.sh"
if [ "$sanitize" = 1 ]; then
  sanitize_log="${GEOSTATION_SANITIZE_BUILD_DIR:-$source_dir/build-sanitize}.build.log"
  nice -n 19 "$source_dir/scripts/sanitize.sh" --build-only > "$sanitize_log" 2>&1 &
  sanitize_build=$!
fi
cd "$build_dir"
status=0
if [ "$sanitize" = 1 ]; then
  # each core test once: the sanitizer stage runs the core tests (label core); here the rest, and the core
  # tests it leaves out or runs on a shorter scene (label core-optimised: timings, the longest scenes)
  ctest -j"$(nproc)" --output-on-failure --timeout 900 -LE '^core$' "$@" || status=$?
else
  ctest -j"$(nproc)" --output-on-failure --timeout 900 "$@" || status=$?
fi
if [ "$sanitize" = 1 ]; then
  if ! wait "$sanitize_build"; then
    cat "$sanitize_log"
    echo "The sanitizer build failed (its log above: $sanitize_log)."
    exit 1
  fi
  echo "The sanitizer build is done (log: $sanitize_log)."
  [ "$status" = 0 ] || exit "$status"
  "$source_dir/scripts/sanitize.sh" --tests-only
fi
exit "$status"
