"""Runs inside QGIS desktop (qgis.bin --code this_file) with the GeoStation
plugin: opens a simulated highway block, navigates the Multiview with the
keyboard, clicks the true pixel of a pole foot in the first view with QTest,
accepts the proposed matches, and records what went into the GeoPackage;
then traces the kerb from one click with the Trace tool and writes it (F);
then saves the project, reopens it and records the restored session; then
measures the pole again with its layer in editing and quits, answering
QGIS's question about the unsaved edits with Save.
Screenshots of the Multiview and the Overview are saved. Driven by
test_desktop_multiview.py, which checks the findings against the truth."""

import json
import os
import sys
import time
import traceback

from qgis.core import QgsPointXY, QgsProject, QgsVectorLayer
from qgis.gui import QgsMapCanvas
from qgis.PyQt.QtCore import QObject, Qt, QTimer
from qgis.PyQt.QtTest import QTest
from qgis.PyQt.QtWidgets import QAction, QComboBox, QDockWidget, QLabel, QMessageBox
from qgis.utils import iface

sys.path.insert(0, os.environ["GEOSTATION_E2E_SCRIPTS"])
from desktop_script_support import checkpoint, finish, invoke, wait  # noqa: E402

RESULT = os.environ["GEOSTATION_E2E_RESULT"]
ARTIFACTS = os.environ["GEOSTATION_E2E_ARTIFACTS"]
BLOCK = os.environ["GEOSTATION_E2E_BLOCK"]
TARGET = os.environ["GEOSTATION_E2E_TARGET"]
PROJECT = os.environ["GEOSTATION_E2E_PROJECT"]
CLICK = json.loads(os.environ["GEOSTATION_E2E_CLICK"])  # station, image, col, row
TRACE = json.loads(os.environ["GEOSTATION_E2E_TRACE"])  # col, row of a kerb pixel in the same image
LANE = json.loads(os.environ["GEOSTATION_E2E_LANE"])  # col, row of a dash of the lane line in the first station's first image


def dock_state(dock):
    views = []
    for i in range(6):
        view = dock.findChild(QObject, "mGeoStationImageView%d" % i)
        if view is None:
            continue
        status = view.findChild(QLabel, "mStatus")
        canvas = view.findChild(QgsMapCanvas, "mGeoStationViewCanvas%d" % i)
        views.append({"status": status.text() if status else None,
                      "layers": [l.name() for l in canvas.layers()] if canvas else []})
    return {"title": dock.windowTitle(), "views": views}


def run():
    result = {}
    try:
        window = iface.mainWindow()
        plugin = window.findChild(QObject, "GeoStationPlugin")
        result["plugin"] = plugin is not None
        result["block_opened"] = invoke(plugin, "openBlockFile", BLOCK, returns=bool)
        result["classes_set"] = invoke(plugin, "setFeatureClassesJson", json.dumps([
            {"name": "Pole", "geometry": "point", "attributes": {"kind": "pole"}},
            {"name": "Road edge", "geometry": "line"},
            {"name": "Lane marking", "geometry": "line"}]), returns=bool)
        result["target_set"] = invoke(plugin, "setTargetGeoPackage", TARGET, returns=bool)
        checkpoint(result, RESULT, "opening the Multiview")
        window.findChild(QAction, "mActionGeoStationMultiview").trigger()
        window.showMaximized()
        wait(1.0)
        dock = window.findChild(QDockWidget, "GeoStationMultiviewDock")
        result["dock"] = dock is not None
        result["overview_layers"] = sorted(l.name() for l in QgsProject.instance().mapLayers().values())

        checkpoint(result, RESULT, "navigating")
        # navigate with the keyboard: from the first station to the one with the pole
        canvas0 = dock.findChild(QgsMapCanvas, "mGeoStationViewCanvas0")
        canvas0.setFocus()
        QTest.keyClick(canvas0, Qt.Key_End)
        wait(0.3)
        result["after_end"] = dock_state(dock)["title"]
        QTest.keyClick(canvas0, Qt.Key_Home)
        wait(0.3)
        steps = []
        for _ in range(CLICK["station_index"]):
            QTest.keyClick(canvas0, Qt.Key_PageDown)
            wait(0.4)
            steps.append(dock.property("lastNavigationMs"))
        result["navigation_ms"] = steps
        result["at_station"] = dock_state(dock)

        checkpoint(result, RESULT, "clicking")
        # click the pole foot, zoomed in so one screen pixel is a fraction of an image pixel
        invoke(dock, "zoomViewToPixel", 0, float(CLICK["col"]), float(CLICK["row"]), 40.0)
        wait(0.5)
        screen = canvas0.getCoordinateTransform().transform(QgsPointXY(CLICK["col"], -CLICK["row"]))
        pos = screen.toQPointF().toPoint()
        clicked = canvas0.getCoordinateTransform().toMapCoordinates(pos.x(), pos.y())
        result["clicked_pixel"] = [clicked.x(), -clicked.y()]
        QTest.mouseClick(canvas0.viewport(), Qt.LeftButton, Qt.NoModifier, pos)
        wait(0.5)
        result["proposal_ms"] = dock.property("lastProposalMs")
        result["after_click"] = dock_state(dock)
        dock.grab().save(os.path.join(ARTIFACTS, "multiview-proposals.png"))

        checkpoint(result, RESULT, "accepting")
        # accept the proposed matches (Return)
        QTest.keyClick(canvas0, Qt.Key_Return)
        wait(1.0)
        result["messages"] = invoke(dock, "messagesText", returns=str)
        layer = QgsVectorLayer(TARGET + "|layername=pole", "pole", "ogr")
        result["features"] = [{"x": f.geometry().constGet().x(), "y": f.geometry().constGet().y(), "z": f.geometry().constGet().z(),
                               "sigma": [f["sigma_x"], f["sigma_y"], f["sigma_z"]], "method": f["method"],
                               "n_images": f["n_images"], "station": f["station"], "class": f["class"]}
                              for f in layer.getFeatures()] if layer.isValid() else []
        wait(0.5)
        dock.grab().save(os.path.join(ARTIFACTS, "multiview-measured.png"))
        iface.mapCanvas().refreshAllLayers()
        wait(1.0)
        window.grab().save(os.path.join(ARTIFACTS, "overview.png"))

        checkpoint(result, RESULT, "tracing")
        # the Trace tool: a line class, one click on the kerb, the run traced; F writes it
        combo = dock.findChild(QComboBox, "mClassCombo")
        combo.setCurrentIndex(combo.findData("Road edge"))
        combo.activated.emit(combo.currentIndex())
        dock.findChild(QAction, "mActionTrace").setChecked(True)
        invoke(dock, "zoomViewToPixel", 0, float(TRACE["col"]), float(TRACE["row"]), 40.0)
        wait(0.5)
        screen = canvas0.getCoordinateTransform().transform(QgsPointXY(TRACE["col"], -TRACE["row"]))
        started = time.time()
        QTest.mouseClick(canvas0.viewport(), Qt.LeftButton, Qt.NoModifier, screen.toQPointF().toPoint())
        status = dock.findChild(QLabel, "mTraceStatus")
        while time.time() - started < 90 and "stopped" not in status.text():
            wait(0.1)
        result["trace_seconds"] = time.time() - started
        result["trace_status"] = status.text()
        invoke(dock, "zoomViewToPixel", 0, float(TRACE["col"]), float(TRACE["row"]), 400.0)
        iface.mapCanvas().zoomScale(1500)
        wait(1.0)
        dock.grab().save(os.path.join(ARTIFACTS, "multiview-traced.png"))
        window.grab().save(os.path.join(ARTIFACTS, "overview-traced.png"))
        QTest.keyClick(canvas0, Qt.Key_F)
        wait(1.0)
        result["trace_messages"] = invoke(dock, "messagesText", returns=str)
        edges = QgsVectorLayer(TARGET + "|layername=road_edge", "road_edge", "ogr")
        result["traced"] = [{"method": f["method"], "station": f["station"], "class": f["class"],
                             "vertices": [[v.x(), v.y(), v.z()] for v in f.geometry().vertices()]}
                            for f in edges.getFeatures()] if edges.isValid() else []
        vertices = QgsVectorLayer(TARGET + "|layername=vertices", "vertices", "ogr")
        result["traced_vertex_rows"] = len([f for f in vertices.getFeatures() if f["layer"] == "road_edge"]) if vertices.isValid() else 0
        # the dashed lane line into its own class: one click on a dash at the first station
        QTest.keyClick(canvas0, Qt.Key_Home)
        wait(0.5)
        combo.setCurrentIndex(combo.findData("Lane marking"))
        combo.activated.emit(combo.currentIndex())
        invoke(dock, "zoomViewToPixel", 0, float(LANE["col"]), float(LANE["row"]), 40.0)
        wait(0.5)
        screen = canvas0.getCoordinateTransform().transform(QgsPointXY(LANE["col"], -LANE["row"]))
        started = time.time()
        before = status.text()
        QTest.mouseClick(canvas0.viewport(), Qt.LeftButton, Qt.NoModifier, screen.toQPointF().toPoint())
        wait(0.2)
        while time.time() - started < 90 and "stopped" not in status.text():
            wait(0.1)
        result["lane_status"] = status.text()
        invoke(dock, "zoomViewToPixel", 0, float(LANE["col"]), float(LANE["row"]), 400.0)
        wait(0.5)
        dock.grab().save(os.path.join(ARTIFACTS, "multiview-traced-lane.png"))
        QTest.keyClick(canvas0, Qt.Key_F)
        wait(1.0)
        lanes = QgsVectorLayer(TARGET + "|layername=lane_marking", "lane_marking", "ogr")
        result["lane"] = [{"method": f["method"], "vertices": [[v.x(), v.y(), v.z()] for v in f.geometry().vertices()]}
                          for f in lanes.getFeatures()] if lanes.isValid() else []
        result["lane_messages"] = invoke(dock, "messagesText", returns=str)
        dock.findChild(QAction, "mActionTrace").setChecked(False)

        checkpoint(result, RESULT, "saving the session")
        # the session is kept with the project
        QTest.keyClick(canvas0, Qt.Key_PageDown)
        wait(0.5)
        saved_title = dock_state(dock)["title"]
        result["saved"] = QgsProject.instance().write(PROJECT)
        QgsProject.instance().clear()
        wait(0.5)
        result["after_clear"] = dock_state(dock)["title"]
        checkpoint(result, RESULT, "reopening")
        result["reopened"] = QgsProject.instance().read(PROJECT)
        wait(1.5)
        dock = window.findChild(QDockWidget, "GeoStationMultiviewDock")
        result["restored_title"] = dock_state(dock)["title"] if dock else None
        result["saved_title"] = saved_title
        result["restored_layers"] = sorted(l.name() for l in QgsProject.instance().mapLayers().values())

        checkpoint(result, RESULT, "measuring into an edit buffer")
        # the operator has the pole layer in editing: the pole measured again stays in its edit buffer,
        # and QGIS asks at exit whether to save it (answered Save below; the driver finds it on disk)
        pole = next(l for l in QgsProject.instance().mapLayers().values() if l.name() == "pole")
        result["pole_editing"] = pole.startEditing()
        combo = dock.findChild(QComboBox, "mClassCombo")
        combo.setCurrentIndex(combo.findData("Pole"))
        combo.activated.emit(combo.currentIndex())
        canvas0 = dock.findChild(QgsMapCanvas, "mGeoStationViewCanvas0")
        canvas0.setFocus()
        QTest.keyClick(canvas0, Qt.Key_Home)
        wait(0.3)
        for _ in range(CLICK["station_index"]):
            QTest.keyClick(canvas0, Qt.Key_PageDown)
            wait(0.4)
        result["buffer_station"] = dock_state(dock)["title"]
        invoke(dock, "zoomViewToPixel", 0, float(CLICK["col"]), float(CLICK["row"]), 40.0)
        wait(0.5)
        screen = canvas0.getCoordinateTransform().transform(QgsPointXY(CLICK["col"], -CLICK["row"]))
        QTest.mouseClick(canvas0.viewport(), Qt.LeftButton, Qt.NoModifier, screen.toQPointF().toPoint())
        wait(0.5)
        QTest.keyClick(canvas0, Qt.Key_Return)
        wait(1.0)
        result["buffer_messages"] = invoke(dock, "messagesText", returns=str)
        result["pole_layers"] = [[l.id(), l.source(), l.isEditable()] for l in QgsProject.instance().mapLayers().values() if l.name() == "pole"]
        result["buffered_features"] = len(pole.editBuffer().addedFeatures()) if pole.editBuffer() else 0
        on_disk = QgsVectorLayer(TARGET + "|layername=pole", "pole on disk", "ogr")
        result["poles_on_disk_before_exit"] = on_disk.featureCount() if on_disk.isValid() else -1
        del on_disk
    except Exception:  # reported to the driver, which fails the test
        result["exception"] = traceback.format_exc()
    finish(result, RESULT, answer=lambda text: QMessageBox.Save if "pole" in text else None)


QTimer.singleShot(3000, run)
