#!/usr/bin/env bash
# Builds the libFuzzer program (clang, AddressSanitizer + UndefinedBehaviorSanitizer,
# coverage) and fuzzes every target for a while, starting from its seed corpus in
# tests/fuzz/corpus/<target>. New inputs that reach new code go to
# build-fuzz/corpus/<target> (kept between runs); a crash leaves its input as
# build-fuzz/findings/<target>/crash-* and fails the run: copy it to
# tests/fuzz/regressions/<target>/ and fix the reader (the replay tests run it).
#
#   scripts/fuzz.sh [seconds per target (60)] [target...]
#
# A longer run of one target, on both cores:
#   scripts/fuzz.sh 3600 block_json
set -euo pipefail
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${GEOSTATION_FUZZ_BUILD_DIR:-$source_dir/build-fuzz}"
seconds="${1:-60}"
shift || true
targets=("$@")
if [ "${#targets[@]}" = 0 ]; then
  targets=(block_json colmap_text colmap_binary trajectory_csv events_csv metashape_xml opencv_calibration raster dem)
fi
command -v clang++ > /dev/null || sudo apt-get install -y clang
mkdir -p "$build_dir"
cmake -S "$source_dir" -B "$build_dir" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1" -DGEOSTATION_SANITIZE=address,undefined -DGEOSTATION_FUZZ=ON \
  -DGEOSTATION_BUILD_PLUGIN=OFF -DGEOSTATION_BUILD_BENCH=OFF > "$build_dir.configure.log" 2>&1 \
  || { cat "$build_dir.configure.log"; exit 1; }
cmake --build "$build_dir" -j"$(nproc)" --target geostation_fuzz
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
failed=0
summary=""
for target in "${targets[@]}"; do
  corpus="$build_dir/corpus/$target"
  findings="$build_dir/findings/$target"
  mkdir -p "$corpus" "$findings"
  log="$build_dir/findings/$target.log"
  echo "fuzzing $target for $seconds s"
  # -rss_limit_mb: an input that makes a reader take more memory than this is a finding too
  if GEOSTATION_FUZZ_TARGET="$target" "$build_dir/tests/fuzz/geostation_fuzz" -max_total_time="$seconds" \
       -rss_limit_mb=2048 -max_len=65536 -timeout=20 -print_final_stats=1 -artifact_prefix="$findings/" \
       "$corpus" "$source_dir/tests/fuzz/corpus/$target" > "$log" 2>&1; then
    result="ok"
  else
    result="FINDING (see $log and $findings)"
    failed=1
  fi
  runs="$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')"
  summary+="$(printf '%-20s %10s runs  %s' "$target" "$runs" "$result")"$'\n'
done
echo
echo "target               executions"
printf '%s' "$summary"
exit "$failed"
