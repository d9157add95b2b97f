#!/usr/bin/env bash
# Builds the core library and its tests with sanitizers and runs the tests
# under them: AddressSanitizer + UndefinedBehaviorSanitizer by default, or
# ThreadSanitizer (--thread) for the threaded code (image caches, rendering
# threads, background tracing). Any finding fails the run.
#
#   scripts/sanitize.sh [--thread] [--build-only | --tests-only] [gtest filter]
#
# --build-only builds and stops; --tests-only runs the tests of an earlier
# --build-only (scripts/test.sh builds while the main tests run).
#
# Build directory: build-sanitize/ (build-tsan/ for --thread), or
# $GEOSTATION_SANITIZE_BUILD_DIR.
set -euo pipefail
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
sanitizers="address,undefined"
default_dir="$source_dir/build-sanitize"
build=1
run=1
while [ $# -gt 0 ]; do
  case "$1" in
    --thread) sanitizers="thread"; default_dir="$source_dir/build-tsan" ;;
    --build-only) run=0 ;;
    --tests-only) build=0 ;;
    *) break ;;
  esac
  shift
done
filter="${1:-*}"
build_dir="${GEOSTATION_SANITIZE_BUILD_DIR:-$default_dir}"
if [ "$build" = 1 ]; then
  mkdir -p "$build_dir"
  # line tables only (-g1): reports keep file and line, the build and its link are much lighter than with -g
  # -O1 (GEOSTATION_SANITIZE_OPT=-O2 for more): UndefinedBehaviorSanitizer at -O2 makes the build 1.7 times as long
  # (12 minutes against 7 on two cores) and the tests run only 15 % faster
  source "$source_dir/scripts/lib/generator.sh"
  # shellcheck disable=SC2046 # the generator option is one word pair or nothing
  cmake $(cmake_generator_args "$build_dir") -S "$source_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="${GEOSTATION_SANITIZE_OPT:--O1} -g1 -DNDEBUG" -DGEOSTATION_SANITIZE="$sanitizers" \
    -DGEOSTATION_BUILD_PLUGIN=OFF -DGEOSTATION_BUILD_BENCH=OFF > "$build_dir.configure.log" 2>&1 \
    || { cat "$build_dir.configure.log"; exit 1; }
  cmake --build "$build_dir" -j"$(nproc)" --target geostation_core_tests geostation_fuzz_replay
fi
[ "$run" = 1 ] || exit 0
# detect_stack_use_after_return doubles the run time of the Eigen-heavy tests (fake stack frames for every
# call): GEOSTATION_ASAN_OPTIONS=...:detect_stack_use_after_return=1 turns it on for a deeper run
export ASAN_OPTIONS="${GEOSTATION_ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1:strict_string_checks=1}"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
export TSAN_OPTIONS="halt_on_error=1:second_deadlock_stack=1:suppressions=$source_dir/scripts/tsan.supp"
echo "Core tests under -fsanitize=$sanitizers:"
if [ "$filter" = "*" ]; then
  # every core test, through CTest, as many at a time as there are cores
  cd "$build_dir"
  ctest -L core -j"$(nproc)" --output-on-failure --timeout 1800
else
  "$build_dir/tests/core/geostation_core_tests" --gtest_filter="$filter" --gtest_brief=1
fi
