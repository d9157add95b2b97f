#!/usr/bin/env bash
# GeoStation quick demo: installs missing Debian packages, builds, installs the
# plugin into your QGIS profile, simulates the embedded demo data (a highway run
# and an oblique photo) and runs the main jobs headless on it, printing what
# they produced.
#
#   scripts/demo.sh [--gui] [--out DIR]
#
# --gui   afterwards opens QGIS with the plugin and the demo project loaded
# --out   where the demo data and results go (default: demo-out/)
set -euo pipefail
# a failing step says which, instead of ending the demo without a word
trap 'echo "demo.sh: failed (exit $?) at line $LINENO: $BASH_COMMAND" >&2' ERR
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="$source_dir/demo-out"
gui=0
while [ $# -gt 0 ]; do
  case "$1" in
    --gui) gui=1; shift ;;
    --out) out="$2"; shift 2 ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) echo "demo.sh: unknown option $1 (see --help)" >&2; exit 2 ;;
  esac
done

# only what building and running needs (the tests' packages come with scripts/test.sh)
"$source_dir/scripts/setup-debian.sh" --runtime
mkdir -p "${GEOSTATION_BUILD_DIR:-$source_dir/build}"
echo "Building the plugin and the Processing provider (no tests; about 6 minutes on two cores the first time):"
"$source_dir/scripts/build.sh" --demo
"$source_dir/scripts/install-plugin.sh" --build-dir "${GEOSTATION_BUILD_DIR:-$source_dir/build}"

rm -rf "$out"
mkdir -p "$out"
out="$(cd "$out" && pwd)"
export QT_QPA_PLATFORM=offscreen

# qgis_process.bin with its output on stdout; when it fails, its own error (the last lines QGIS wrote, without
# the start-up noise) and the demo stops there
qgis() {
  local log="$out/qgis_process.log"
  if ! { qgis_process.bin "$@" 2> "$log.err" | tee "$log"; }; then
    echo "demo.sh: qgis_process.bin $1 $2 failed:" >&2
    cat "$log" "$log.err" | grep -v -e XDG_RUNTIME_DIR -e "^$" | tail -n 15 >&2
    exit 1
  fi
}
echo "Simulating a highway run (30 stations x 3 cameras) and an oblique photo (geostation:simulate_survey):"
for preset in highway oblique_photo; do
  qgis run geostation:simulate_survey -- PRESET=$preset SEED=1 OUTPUT_DIR="$out/$preset" \
    | grep -E "^(IMAGES|BLOCK):" | sort -u
done

image=S0003_FL
echo
echo "Projecting the surveyed objects into image $image (geostation:project_to_image):"
qgis run geostation:project_to_image -- \
  BLOCK="$out/highway/block.geostation.json" IMAGE="$image" INPUT="$out/highway/truth.gpkg|layername=objects" \
  OUTPUT="$out/${image}_objects.gpkg" | grep -E "^(PROJECTED_COUNT|IN_FRAME_COUNT|BEHIND_CAMERA_COUNT|OUTPUT):" | sort -u

echo
echo "Draping the road lines over the terrain into the oblique photo (geostation:project_to_image with DEM):"
qgis run geostation:project_to_image -- \
  BLOCK="$out/oblique_photo/block.geostation.json" IMAGE=S0001 INPUT="$out/oblique_photo/truth.gpkg|layername=roads" \
  DEM="$out/oblique_photo/terrain.tif" OUTPUT="$out/oblique_roads.gpkg" \
  | grep -E "^(PROJECTED_COUNT|IN_FRAME_COUNT|OUTPUT):" | sort -u

echo
echo "Tracing the dashed lane line and the kerb from one click each in S0003_FL (geostation:trace_road_lines):"
/usr/bin/python3 "$source_dir/scripts/demo_seeds.py" "$out/highway" S0003_FL S0003_FR "$out/seeds.csv"
qgis run geostation:trace_road_lines -- \
  BLOCK="$out/highway/block.geostation.json" SEEDS="$out/seeds.csv" OUTPUT="$out/traced_lines.gpkg" \
  VERTICES="$out/traced_vertices.csv" | sed 's/^[0-9.]*//' | grep -E "^(Seed |TRACED_COUNT|FAILED_COUNT|OUTPUT):?" | sort -u

/usr/bin/python3 "$source_dir/scripts/demo_project.py" "$out" "$image" "$out/highway/images/$image.tif" \
  2> >(grep -v -e XDG_RUNTIME_DIR -e "pixel/line and georeferenced" >&2)

if [ "$gui" = 1 ]; then
  unset QT_QPA_PLATFORM
  exec qgis.bin --nologo "$out/demo.qgz"
fi
echo
echo "Measure in QGIS: scripts/demo.sh --gui   (or: qgis $out/demo.qgz — the run in the Multiview and the Overview)"
