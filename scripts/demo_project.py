#!/usr/bin/python3
"""Prints the demo's results and writes two projects:
- OUT_DIR/demo.qgz: the simulated highway run ready to measure: terrain and
  road lines as the base map (and the lines demo.sh traced headless), the GeoStation session (block, station S0003,
  feature classes, measurements.gpkg beside the block). Opened in QGIS with
  the plugin, it shows the Multiview and the Overview.
- OUT_DIR/image_demo.qgz: one image in pixel space (no CRS) with the
  projected objects on top, in the same frame.

    demo_project.py OUT_DIR IMAGE_ID IMAGE_PATH
"""

import os
import sys

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
from qgis.core import (QgsApplication, QgsCoordinateReferenceSystem, QgsProject,  # noqa: E402
                       QgsRasterLayer, QgsVectorLayer)


FEATURE_CLASSES = [
    {"name": "Pole", "geometry": "point", "attributes": {"kind": "pole"}},
    {"name": "Sign", "geometry": "point", "attributes": {"kind": "sign"}},
    {"name": "Manhole", "geometry": "point", "attributes": {"kind": "manhole"}},
    {"name": "Road edge", "geometry": "line", "attributes": {}},
    {"name": "Lane marking", "geometry": "line", "attributes": {}},
    {"name": "Paved area", "geometry": "polygon", "attributes": {}},
]


def write_multiview_project(out_dir):
    """The measuring project: base map plus the GeoStation session entries
    (the format the plugin writes into every project it saves)."""
    import json
    project = QgsProject.instance()
    project.clear()
    project.setCrs(QgsCoordinateReferenceSystem("EPSG:32617"))
    run = os.path.join(out_dir, "highway")
    terrain = QgsRasterLayer(os.path.join(run, "terrain.tif"), "terrain")
    roads = QgsVectorLayer(os.path.join(run, "truth.gpkg") + "|layername=roads", "road lines (survey)", "ogr")
    for layer in (terrain, roads):
        if not layer.isValid():
            sys.exit("demo_project.py: cannot read " + layer.source())
        project.addMapLayer(layer)
    # the lines demo.sh traced headless, when it did
    traced = QgsVectorLayer(os.path.join(out_dir, "traced_lines.gpkg"), "traced lines (geostation:trace_road_lines)", "ogr")
    if traced.isValid():
        project.addMapLayer(traced)
    path = os.path.join(out_dir, "demo.qgz")
    project.setFileName(path)
    scope = "GeoStation"
    project.writeEntry(scope, "block", "./highway/block.geostation.json")
    project.writeEntry(scope, "station", "S0003")
    project.writeEntry(scope, "featureClasses", json.dumps(FEATURE_CLASSES))
    project.writeEntry(scope, "currentClass", "Pole")
    project.writeEntry(scope, "target", "./measurements.gpkg")
    project.writeEntryDouble(scope, "cameraHeightAboveRoad", 2.6)
    project.writeEntryDouble(scope, "roadPlaneSigma", 0.05)
    if not project.write(path):
        sys.exit("demo_project.py: cannot write " + path)
    print("\nwrote " + path + " (the highway run, ready to measure in the Multiview)")


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

    write_multiview_project(out_dir)
    project = QgsProject.instance()
    project.clear()
    project.setCrs(QgsCoordinateReferenceSystem())  # pixel space: x = col, y = -row
    image = QgsRasterLayer(image_path, image_id)
    project.addMapLayer(image)
    project.addMapLayer(points)
    points.renderer().symbol().setSize(3.0)
    points.renderer().symbol().setColor(points.renderer().symbol().color().fromRgb(220, 30, 30))
    path = os.path.join(out_dir, "image_demo.qgz")
    if not project.write(path):
        sys.exit("demo_project.py: cannot write " + path)
    print("\nwrote " + path)
    app.exitQgis()


if __name__ == "__main__":
    main(*sys.argv[1:4])
