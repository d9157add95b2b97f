#!/usr/bin/python3
"""Prints the demo's results and writes OUT_DIR/demo.qgz: the image in pixel
space (no CRS) with the projected points on top, in the same frame.

    demo_project.py OUT_DIR IMAGE_ID IMAGE_PATH
"""

import os
import sys

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
from qgis.core import (QgsApplication, QgsCoordinateReferenceSystem, QgsProject,  # noqa: E402
                       QgsRasterLayer, QgsVectorLayer)


def main(out_dir, image_id, image_path):
    app = QgsApplication([], False)
    app.initQgis()
    points_path = os.path.join(out_dir, image_id + "_objects.gpkg")
    points = QgsVectorLayer(points_path, "objects in " + image_id, "ogr")
    if not points.isValid():
        sys.exit("demo_project.py: cannot read " + points_path)

    print("\n%-18s %9s %9s %9s  %s" % ("object", "col", "row", "depth_m", "in frame"))
    for f in sorted(points.getFeatures(), key=lambda f: f["id"]):
        col, row, depth = f["col"], f["row"], f["depth_m"]
        fmt = lambda v: "%9.2f" % v if isinstance(v, float) else "%9s" % "-"  # noqa: E731
        print("%-18s %s %s %s  %s" % (f["id"], fmt(col), fmt(row), fmt(depth), "yes" if f["in_frame"] else "no"))

    project = QgsProject.instance()
    project.setCrs(QgsCoordinateReferenceSystem())  # pixel space: x = col, y = -row
    image = QgsRasterLayer(image_path, image_id)
    project.addMapLayer(image)
    project.addMapLayer(points)
    points.renderer().symbol().setSize(3.0)
    points.renderer().symbol().setColor(points.renderer().symbol().color().fromRgb(220, 30, 30))
    path = os.path.join(out_dir, "demo.qgz")
    if not project.write(path):
        sys.exit("demo_project.py: cannot write " + path)
    print("\nwrote " + path)
    app.exitQgis()


if __name__ == "__main__":
    main(*sys.argv[1:4])
