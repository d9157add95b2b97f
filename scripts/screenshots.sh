#!/usr/bin/env bash
# Regenerates the user guide's pictures (docs/images/) from the screenshots
# the desktop tests take of QGIS with GeoStation under xvfb-run, so the
# pictures show the GUI as it is. Needs a build with its tests
# (scripts/build.sh); runs the three desktop tests (about 2 minutes).
#
#   scripts/screenshots.sh
set -euo pipefail
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${GEOSTATION_BUILD_DIR:-$source_dir/build}"
[ -f "$build_dir/CTestTestfile.cmake" ] || { echo "screenshots.sh: no build with tests in $build_dir (scripts/build.sh first)" >&2; exit 1; }
(cd "$build_dir" && ctest -R '^e2e_desktop_(smoke|multiview|orientation)$' --output-on-failure)
# the test's picture -> the guide's (the pages name these)
/usr/bin/python3 - "$build_dir/test-artifacts" "$source_dir/docs/images" <<'PY'
import os
import shutil
import sys

artifacts, images = sys.argv[1:3]
pictures = {
    "multiview-measured.png": "multiview-measured.png",        # a pole measured in two views, with its sigma
    "multiview-traced-lane.png": "multiview-traced-lane.png",  # a lane line traced through the run from one click
    "overview.png": "overview.png",                            # the map: trajectory, stations, view cones
    "orientation-clicked.png": "orientation-clicked.png",      # control points clicked, residuals
    "orientation-accepted.png": "orientation-accepted.png",    # the fiducials and the control found, accepted
}
os.makedirs(images, exist_ok=True)
try:
    from PIL import Image  # python3-pil, when present: 256 colours keep the pages light
except ImportError:
    Image = None
for source, target in pictures.items():
    path = os.path.join(artifacts, source)
    if not os.path.isfile(path):
        sys.exit("screenshots.sh: the desktop tests did not save " + source)
    out = os.path.join(images, target)
    if Image:
        Image.open(path).convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE).save(out, optimize=True)
    else:
        shutil.copyfile(path, out)
    print("%s (%d kB)" % (out, os.path.getsize(out) // 1024))
PY
