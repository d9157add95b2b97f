"""Runs inside QGIS desktop (qgis.bin --code this_file) with the GeoStation
plugin: adds a scanned oblique photo to a new block (Add Photo), detects its
fiducials, loads the control layer, clicks four control points in the
Multiview's view of the photo with QTest, lets the semi-automatic mode find
the rest, accepts them, saves the orientation, then digitises a road in the
photo (monoplotted on the DEM layer) into a GeoPackage. Driven by
test_desktop_orientation.py, which checks the findings against the truth."""

import json
import os
import sys
import traceback

from qgis.core import QgsCoordinateReferenceSystem, QgsPointXY, QgsProject, QgsRasterLayer, QgsVectorLayer
from qgis.gui import QgsMapCanvas
from qgis.PyQt.QtCore import QObject, Qt, QTimer
from qgis.PyQt.QtTest import QTest
from qgis.PyQt.QtWidgets import QCheckBox, QComboBox, QDockWidget, QLabel, QPlainTextEdit, QPushButton, QTableView, QToolButton
from qgis.utils import iface

sys.path.insert(0, os.environ["GEOSTATION_E2E_SCRIPTS"])
from desktop_script_support import checkpoint, finish, invoke, wait  # noqa: E402

RESULT = os.environ["GEOSTATION_E2E_RESULT"]
ARTIFACTS = os.environ["GEOSTATION_E2E_ARTIFACTS"]
PHOTO = os.environ["GEOSTATION_E2E_PHOTO"]
BLOCK = os.environ["GEOSTATION_E2E_BLOCK"]
CAMERA = os.environ["GEOSTATION_E2E_CAMERA"]
CRS = os.environ["GEOSTATION_E2E_CRS"]
DEM = os.environ["GEOSTATION_E2E_DEM"]
CONTROL = os.environ["GEOSTATION_E2E_CONTROL"]
CLICKS = json.loads(os.environ["GEOSTATION_E2E_CLICKS"])  # id, col, row of four control points
ROAD = json.loads(os.environ["GEOSTATION_E2E_ROAD"])  # col, row of five road vertices
TARGET = os.environ["GEOSTATION_E2E_TARGET"]


def click_pixel(multiview, canvas, col, row):
    """A real mouse click on an image pixel of the first view, zoomed in so a screen pixel is a fraction of an image pixel."""
    invoke(multiview, "zoomViewToPixel", 0, float(col), float(row), 40.0)
    wait(0.4)
    screen = canvas.getCoordinateTransform().transform(QgsPointXY(col, -row))
    QTest.mouseClick(canvas.viewport(), Qt.LeftButton, Qt.NoModifier, screen.toQPointF().toPoint())
    wait(0.3)


def run():
    result = {}
    try:
        window = iface.mainWindow()
        window.showMaximized()
        plugin = window.findChild(QObject, "GeoStationPlugin")
        QgsProject.instance().setCrs(QgsCoordinateReferenceSystem(CRS))
        dem = QgsRasterLayer(DEM, "terrain")
        control = QgsVectorLayer(CONTROL, "control points", "ogr")
        QgsProject.instance().addMapLayers([dem, control])
        iface.mapCanvas().setExtent(control.extent())

        checkpoint(result, RESULT, "adding the photo")
        result["image_id"] = invoke(plugin, "addPhotoFile", PHOTO, BLOCK, CAMERA, returns=str)
        invoke(plugin, "setDemLayer", dem.id())
        wait(1.0)
        dock = window.findChild(QDockWidget, "GeoStationOrientationDock")
        multiview = window.findChild(QDockWidget, "GeoStationMultiviewDock")
        result["orientation_dock"] = dock is not None
        canvas = multiview.findChild(QgsMapCanvas, "mGeoStationViewCanvas0")
        result["view_image"] = [l.name() for l in canvas.layers()][0] if canvas.layers() else None
        result["photo_choice"] = dock.findChild(QComboBox, "mImageCombo").currentText()

        checkpoint(result, RESULT, "fiducials")
        detect = dock.findChild(QToolButton, "mDetectButton")
        detect.click()
        # the detection runs in the background: the button reads "Cancel Detection" until it ends
        for _ in range(120):
            wait(0.25)
            if detect.text() == "Detect Fiducials":
                break
        result["fiducials"] = dock.findChild(QLabel, "mResultLabel").text()

        checkpoint(result, RESULT, "control layer")
        layers = dock.findChild(QComboBox, "mControlLayerCombo")
        layers.setCurrentIndex(layers.findText(control.name()))
        dock.findChild(QPushButton, "mLoadControlButton").click()
        result["loaded"] = dock.findChild(QLabel, "mMessageLabel").text()
        table = dock.findChild(QTableView, "mTable")
        model = table.model()
        rows = {model.index(r, 0).data(): r for r in range(model.rowCount())}

        checkpoint(result, RESULT, "clicking control")
        dock.findChild(QToolButton, "mMeasurePhotoButton").setChecked(True)
        for click in CLICKS:
            table.selectRow(rows[click["id"]])
            click_pixel(multiview, canvas, click["col"], click["row"])
        results_text = dock.findChild(QPlainTextEdit, "mResultText")
        result["after_clicks"] = results_text.toPlainText()
        invoke(multiview, "zoomViewToPixel", 0, 512.0, 384.0, 600.0)
        wait(0.5)
        window.grab().save(os.path.join(ARTIFACTS, "orientation-clicked.png"))

        checkpoint(result, RESULT, "semi-automatic")
        dock.findChild(QToolButton, "mPredictButton").click()
        wait(0.5)
        result["offers"] = dock.findChild(QLabel, "mMessageLabel").text()
        result["offers_found"] = sum(1 for r in range(model.rowCount()) if model.index(r, 13).data() == "offered: found")
        dock.findChild(QToolButton, "mAcceptButton").click()
        wait(0.3)
        result["after_accept"] = results_text.toPlainText()
        result["measured_after_accept"] = sum(1 for r in range(model.rowCount()) if model.index(r, 13).data() in ("ok", "check"))
        window.grab().save(os.path.join(ARTIFACTS, "orientation-accepted.png"))

        checkpoint(result, RESULT, "saving")
        dock.findChild(QPushButton, "mSaveButton").click()
        wait(1.5)
        result["save_message"] = dock.findChild(QLabel, "mMessageLabel").text()
        result["saved"] = "is saved in" in result["save_message"]
        result["photo_choice_saved"] = dock.findChild(QComboBox, "mImageCombo").currentText()
        result["camera_line_saved"] = dock.findChild(QLabel, "mCameraLabel").text()
        dock.findChild(QToolButton, "mMeasurePhotoButton").setChecked(False)

        checkpoint(result, RESULT, "map layer in the photo")
        roads_map = QgsVectorLayer(CONTROL.split("|")[0] + "|layername=roads", "road map", "ogr")
        QgsProject.instance().addMapLayer(roads_map)
        overlay = dock.findChild(QComboBox, "mOverlayLayerCombo")
        overlay.setCurrentIndex(overlay.findText(roads_map.name()))
        dock.findChild(QCheckBox, "mShowOverlayCheck").setChecked(True)
        invoke(multiview, "zoomViewToPixel", 0, 512.0, 384.0, 600.0)
        wait(1.0)
        multiview.grab().save(os.path.join(ARTIFACTS, "orientation-map-layer.png"))
        dock.findChild(QCheckBox, "mShowOverlayCheck").setChecked(False)

        checkpoint(result, RESULT, "digitising")
        invoke(plugin, "setFeatureClassesJson", json.dumps([{"name": "Road", "geometry": "line"}]), returns=bool)
        invoke(plugin, "setCurrentClass", "Road")
        invoke(plugin, "setTargetGeoPackage", TARGET, returns=bool)
        wait(0.5)
        for vertex in ROAD:
            click_pixel(multiview, canvas, vertex["col"], vertex["row"])
            QTest.keyClick(canvas, Qt.Key_Return)
            wait(0.3)
        QTest.keyClick(canvas, Qt.Key_F)
        wait(1.0)
        result["road_messages"] = invoke(multiview, "messagesText", returns=str)
        roads = QgsVectorLayer(TARGET + "|layername=road", "road", "ogr")
        vertices = QgsVectorLayer(TARGET + "|layername=vertices", "vertices", "ogr")
        sigmas = sorted(((f["vertex"], [f["sx"], f["sy"], f["sz"]]) for f in vertices.getFeatures() if f["layer"] == "road"),
                        key=lambda v: v[0]) if vertices.isValid() else []
        result["road"] = [{"method": f["method"], "vertices": [[v.x(), v.y(), v.z()] for v in f.geometry().vertices()],
                           "sigmas": [s for _, s in sigmas]} for f in roads.getFeatures()] if roads.isValid() else []
        invoke(multiview, "zoomViewToPixel", 0, 512.0, 384.0, 600.0)
        iface.mapCanvas().refreshAllLayers()
        wait(1.0)
        window.grab().save(os.path.join(ARTIFACTS, "orientation-road.png"))
    except Exception:  # reported to the driver, which fails the test
        result["exception"] = traceback.format_exc()
    finish(result, RESULT)


QTimer.singleShot(3000, run)
