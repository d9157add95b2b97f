#!/usr/bin/env bash
# The road extraction's figures on every case docs/validation.md reports,
# with the defaults, in one run of about half a minute: the simulator's three
# pairs, the painted scenes (0.15 m to 10 m), OpenCV's aerial photographs
# and the 10 m image of Chicago - the disabled tests (aims not met) too.
# The extraction responds to a change chaotically (rounds, dead ends
# continued, verification feeding the next round): judge a change on all of
# these, not on one scene. Needs a build with its tests (scripts/build.sh).
#
#   scripts/extraction_figures.sh [extra gtest filter]
set -euo pipefail
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${GEOSTATION_BUILD_DIR:-$source_dir/build}"
tests="$build_dir/tests/core/geostation_core_tests"
[ -x "$tests" ] || { echo "extraction_figures.sh: no $tests (scripts/build.sh first)" >&2; exit 1; }
filter="RoadExtraction.DISABLED_DefaultsOnTheSimulatorsPairs:PaintedRoads.*:RealAerialPhotograph.DefaultsOnTheMainRoads"
filter+=":RealAerialPhotograph.Aero1HighwayWithTheDefaults:RealSatelliteImage.DISABLED_ChicagoMainRoadsWithTheDefaults"
[ -n "${1:-}" ] && filter+=":$1"
# the figures each test prints (not gtest's own lines, nor the failed expectations' detail)
"$tests" --gtest_also_run_disabled_tests --gtest_filter="$filter" 2>&1 |
  grep -E "completeness|correctness|found|main roads" | grep -vE "^(Expected|  Actual|Value of|  Which)" || true
