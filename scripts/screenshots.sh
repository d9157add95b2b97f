#!/usr/bin/env bash
# Regenerates the user guide's pictures (docs/images/) from the screenshots
# the desktop tests take of QGIS with GeoStation under xvfb-run, so the
# pictures show the GUI as it is; a readable report page as the resection
# test writes it and the lines the extraction test finds over its photo. Needs a build with its tests (scripts/build.sh);
# runs the three desktop tests and the resection test (about 2 minutes).
#
#   scripts/screenshots.sh
set -euo pipefail
source_dir="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build_dir="${GEOSTATION_BUILD_DIR:-$source_dir/build}"
[ -f "$build_dir/CTestTestfile.cmake" ] || { echo "screenshots.sh: no build with tests in $build_dir (scripts/build.sh first)" >&2; exit 1; }
(cd "$build_dir" && ctest -R '^e2e_desktop_(smoke|multiview|orientation)$' --output-on-failure)
# a readable report, as the resection test writes it (a blunder among twelve control points)
(cd "$build_dir" && GEOSTATION_TEST_ARTIFACTS="$build_dir/test-artifacts" ctest -R '^processing_(intersect_resection|extract_roads)$' --output-on-failure)
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
    "extraction-left.jpg": "extraction-left.jpg",              # extract_roads' OUTPUT_LEFT drawn over the left photo (a photo: JPEG)
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
    if Image and target.endswith(".png"):
        Image.open(path).convert("RGB").quantize(colors=256, method=Image.Quantize.FASTOCTREE).save(out, optimize=True)
    else:
        shutil.copyfile(path, out)
    print("%s (%d kB)" % (out, os.path.getsize(out) // 1024))
PY
# the report page drawn as QGIS's browser draws it (python3-pyqt5.qtwebkit, which QGIS's Python needs)
QT_QPA_PLATFORM=offscreen /usr/bin/python3 - "$build_dir/test-artifacts/report-resection.html" "$source_dir/docs/images/report-resection.png" <<'PY'
import os
import sys

from PyQt5.QtCore import QSize, QUrl
from PyQt5.QtGui import QImage, QPainter
from PyQt5.QtWidgets import QApplication
from PyQt5.QtWebKitWidgets import QWebPage

source, target = sys.argv[1:3]
if not os.path.isfile(source):
    sys.exit("screenshots.sh: the resection test did not save " + source)
app = QApplication(sys.argv)
page = QWebPage()


def drawn(ok):
    if not ok:
        sys.exit("screenshots.sh: cannot draw " + source)
    frame = page.mainFrame()
    page.setViewportSize(QSize(820, 100))
    page.setViewportSize(QSize(820, frame.contentsSize().height()))
    image = QImage(page.viewportSize(), QImage.Format_RGB32)
    image.fill(0xffffffff)
    painter = QPainter(image)
    frame.render(painter)
    painter.end()
    try:
        from PIL import Image
        import io
        from PyQt5.QtCore import QBuffer
        buffer = QBuffer()
        buffer.open(QBuffer.ReadWrite)
        image.save(buffer, "PNG")
        Image.open(io.BytesIO(bytes(buffer.data()))).convert("RGB").quantize(colors=64, method=Image.Quantize.FASTOCTREE).save(target, optimize=True)
    except ImportError:
        image.save(target)
    print("%s (%d kB)" % (target, os.path.getsize(target) // 1024))
    app.quit()


page.loadFinished.connect(drawn)
page.mainFrame().load(QUrl.fromLocalFile(os.path.abspath(source)))
app.exec_()
PY
