#!/usr/bin/env bash
# GeoStation quick demo: installs missing Debian packages, builds, installs the
# plugin into your QGIS profile and runs the main job headless on the embedded
# demo data, printing what it produced.
#
#   scripts/demo.sh [--gui] [--out DIR]
#
# --gui   afterwards opens QGIS with the plugin and the demo project loaded
# --out   where the demo data and results go (default: demo-out/)
set -euo pipefail
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

"$source_dir/scripts/setup-debian.sh"
mkdir -p "${GEOSTATION_BUILD_DIR:-$source_dir/build}"
"$source_dir/scripts/build.sh" > /dev/null
"$source_dir/scripts/install-plugin.sh" --build-dir "${GEOSTATION_BUILD_DIR:-$source_dir/build}"

rm -rf "$out"
mkdir -p "$out"
out="$(cd "$out" && pwd)"
/usr/bin/python3 "$source_dir/scripts/geostation_demo_data.py" "$out" --stations 8

image=S0003_front_left
export QT_QPA_PLATFORM=offscreen
echo
echo "Projecting the surveyed poles and hydrants into image $image (geostation:project_to_image):"
qgis_process.bin run geostation:project_to_image -- \
  BLOCK="$out/block.geostation.json" IMAGE="$image" INPUT="$out/objects.gpkg" OUTPUT="$out/${image}_objects.gpkg" \
  2>/dev/null | grep -E "^(PROJECTED_COUNT|IN_FRAME_COUNT|BEHIND_CAMERA_COUNT|OUTPUT):" | sort -u

/usr/bin/python3 "$source_dir/scripts/demo_project.py" "$out" "$image" 2> >(grep -v -e XDG_RUNTIME_DIR -e "pixel/line and georeferenced" >&2)

if [ "$gui" = 1 ]; then
  unset QT_QPA_PLATFORM
  exec qgis.bin --nologo "$out/demo.qgz"
fi
echo
echo "Open it in QGIS: scripts/demo.sh --gui   (or: qgis $out/demo.qgz)"
