#!/usr/bin/env bash
# Configures and builds GeoStation in build/ (or $GEOSTATION_BUILD_DIR).
set -euo pipefail
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${GEOSTATION_BUILD_DIR:-$source_dir/build}"
# GEOSTATION_WERROR=ON (CI=true sets it): compiler warnings fail the build
werror="${GEOSTATION_WERROR:-$([ "${CI:-}" = true ] && echo ON || echo OFF)}"
# GEOSTATION_REQUIRE_TEST_TOOLS=ON (CI=true sets it): a program or data package a test needs that is missing
# fails the configuration instead of leaving its tests out
require="${GEOSTATION_REQUIRE_TEST_TOOLS:-$([ "${CI:-}" = true ] && echo ON || echo OFF)}"
# debug information: full (-g) for a developer's build; line tables only (-g1) in CI, where nobody steps
# through the code and -g makes the build about 40 % slower (backtraces keep file and line either way)
debug="${GEOSTATION_DEBUG_INFO:-$([ "${CI:-}" = true ] && echo -g1 || echo -g)}"
# --demo (scripts/demo.sh): the plugin, the provider and the guide only, no tests or benchmarks, and the
# build's progress as one line per tenth instead of every step; otherwise everything (a build folder a
# demo configured gets its tests back)
demo=0
[ "${1:-}" = "--demo" ] && demo=1
# GEOSTATION_CORE_TESTS=optimised (scripts/test.sh, beside its sanitizer build): of the core tests only the groups
# the main stage runs (tests/core/CMakeLists.txt); otherwise all
parts=(-DGEOSTATION_BUILD_TESTS=ON -DGEOSTATION_BUILD_BENCH=ON -DGEOSTATION_CORE_TESTS="${GEOSTATION_CORE_TESTS:-all}")
[ "$demo" = 1 ] && parts=(-DGEOSTATION_BUILD_TESTS=OFF -DGEOSTATION_BUILD_BENCH=OFF)
source "$source_dir/scripts/lib/generator.sh"
# shellcheck disable=SC2046 # the generator option is one word pair or nothing
cmake $(cmake_generator_args "$build_dir") -S "$source_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE="${CMAKE_BUILD_TYPE:-RelWithDebInfo}" -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 $debug -DNDEBUG" \
  -DGEOSTATION_WERROR="$werror" -DGEOSTATION_REQUIRE_TEST_TOOLS="$require" "${parts[@]}" > "$build_dir.configure.log" 2>&1 \
  || { cat "$build_dir.configure.log"; exit 1; }
# the configure log is kept; its warnings (a missing optional package, a deprecated setting) are shown
if grep -q "CMake Warning\|CMake Deprecation Warning" "$build_dir.configure.log"; then
  echo "Configure warnings (full log: $build_dir.configure.log):"
  awk '/^CMake (Deprecation )?Warning/{show=1} show{print} /^$/{if(show)n++; if(n>=2){show=0;n=0}}' "$build_dir.configure.log"
fi
if [ "$demo" = 0 ]; then
  cmake --build "$build_dir" -j"$(nproc)"
  exit 0
fi
# Ninja's "[k/n] ..." lines as "Building: 30 % (k of n steps)"; everything else (a compiler's error) as it comes
cmake --build "$build_dir" -j"$(nproc)" | awk '
  match($0, /^\[[0-9]+\/[0-9]+\]/) {
    split(substr($0, 2, RLENGTH - 2), kn, "/"); tenth = int(10 * kn[1] / kn[2])
    if (tenth > shown) { shown = tenth; printf "Building: %d %% (%d of %d steps)\n", 10 * tenth, kn[1], kn[2]; fflush() }
    next }
  /^ninja: no work to do/ { print "Building: nothing to do (built already)"; next }
  { print; fflush() }'

