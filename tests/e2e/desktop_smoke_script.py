"""Runs inside QGIS desktop (qgis.bin --code this_file): checks that the
GeoStation plugin is loaded, exercises it (blocks good and bad, Block
Information, an algorithm dialog, Import Block through its dialog), writes
the findings as JSON and a screenshot, and quits QGIS. Driven by test_desktop_smoke.py."""

import hashlib
import json
import os
import time
import traceback

from qgis.core import QgsApplication, QgsCoordinateReferenceSystem, QgsProject
from qgis.PyQt.QtCore import Q_ARG, Q_RETURN_ARG, QMetaObject, QObject, Qt, QTimer
from qgis.PyQt.QtWidgets import QAction, QApplication, QDialog, QDialogButtonBox, QDockWidget, QMenu, QTableView, QToolBar
from qgis.utils import iface

RESULT = os.environ["GEOSTATION_SMOKE_RESULT"]
SCREENSHOT = os.environ["GEOSTATION_SMOKE_SCREENSHOT"]
GOOD_BLOCK = os.environ["GEOSTATION_SMOKE_BLOCK"]
BAD_BLOCK = os.environ["GEOSTATION_SMOKE_BAD_BLOCK"]
OBJECTS = os.environ["GEOSTATION_SMOKE_OBJECTS"]
COLMAP_MODEL = os.environ["GEOSTATION_SMOKE_COLMAP"]
IMPORTED_BLOCK = os.environ["GEOSTATION_SMOKE_IMPORTED"]


def message_bar_texts():
    return [{"title": item.title(), "text": item.text(), "level": int(item.level())}
            for item in iface.messageBar().items()]


def open_block(plugin, path):
    return QMetaObject.invokeMethod(plugin, "openBlockFile", Qt.DirectConnection,
                                    Q_RETURN_ARG(bool), Q_ARG(str, path))


def show_block_info(window):
    """Triggers Block Information, and from inside its modal loop records the
    dialog, saves a screenshot of it and closes it."""
    action = window.findChild(QAction, "mActionGeoStationBlockInfo")
    seen = {"action_enabled": bool(action and action.isEnabled())}

    def inspect():
        dialog = QApplication.activeModalWidget()
        seen["dialog"] = dialog.objectName() if dialog else None
        if dialog:
            table = dialog.findChild(QTableView, "mCameraTable")
            seen["camera_rows"] = table.model().rowCount() if table else 0
            seen["screenshot"] = dialog.grab().save(SCREENSHOT.replace(".png", "-block-info.png"))
            dialog.reject()

    if action and action.isEnabled():
        QTimer.singleShot(1000, inspect)
        action.trigger()
    return seen


def open_algorithm_dialog(window, action_name):
    """Triggers a menu action that should open a Processing dialog; records
    the dialog's title from inside its modal loop and closes it."""
    action = window.findChild(QAction, action_name)
    seen = {"tries": 0}

    def inspect():
        # The dialog may take a moment (Processing's Python loads first): retry, bounded.
        dialogs = [w for w in QApplication.topLevelWidgets() if w.isVisible() and isinstance(w, QDialog)]
        dialog = QApplication.activeModalWidget() or (dialogs[0] if dialogs else None)
        seen["tries"] += 1
        if dialog:
            seen["title"] = dialog.windowTitle()
            # QGIS shows the Help button only for an algorithm with a help URL
            boxes = [b for b in dialog.findChildren(QDialogButtonBox) if b.button(QDialogButtonBox.Help)]
            seen["help_button"] = bool(boxes) and boxes[0].button(QDialogButtonBox.Help).isVisibleTo(dialog)
            # the dialog starts with the open block and the first view's image filled in
            try:
                wrappers = dialog.mainWidget().wrappers
                seen["block"] = str(wrappers["BLOCK"].parameterValue()) if "BLOCK" in wrappers else None
                seen["image"] = str(wrappers["IMAGE"].parameterValue()) if "IMAGE" in wrappers else None
            except Exception as e:  # reported: the test compares
                seen["block"] = "could not read the dialog: %s" % e
            dialog.reject()
        elif seen["tries"] < 40:
            QTimer.singleShot(250, inspect)

    if action:
        QTimer.singleShot(250, inspect)
        action.trigger()
        # If the dialog opened non-modally, exec never blocked: give the timer time.
        for _ in range(60):
            if "title" in seen or seen["tries"] >= 40:
                break
            QgsApplication.processEvents()
            time.sleep(0.05)
    return seen


def import_through_the_dialog(window):
    """GeoStation > Import Block...: fills the algorithm dialog with a COLMAP
    model, runs it, closes the dialog when it has finished; then records
    what the plugin opened (the Multiview's title, its views)."""
    action = window.findChild(QAction, "mActionGeoStationImportBlock")
    seen = {"tries": 0}

    def drive():
        # the algorithm dialog, modal or not (under xvfb it need not be the active modal widget)
        dialogs = [w for w in QApplication.topLevelWidgets() if w.isVisible() and hasattr(w, "setParameters")]
        dialog = dialogs[0] if dialogs else None
        seen["tries"] += 1
        if dialog is None:
            if seen["tries"] < 80:
                QTimer.singleShot(250, drive)
            return
        seen["title"] = dialog.windowTitle()

        def finished(successful, results):
            seen["successful"] = successful
            seen["results"] = {k: str(v) for k, v in results.items()}
            QTimer.singleShot(200, dialog.close)

        dialog.algorithmFinished.connect(finished)
        dialog.setParameters({"INPUT": COLMAP_MODEL, "CRS": QgsCoordinateReferenceSystem("EPSG:32617"), "OUTPUT_BLOCK": IMPORTED_BLOCK})
        dialog.runAlgorithm()

    if action is None:
        return seen
    QTimer.singleShot(500, drive)
    action.trigger()  # returns when the dialog has closed and the plugin has opened the block
    for _ in range(40):
        QgsApplication.processEvents()
        time.sleep(0.05)
    dock = window.findChild(QDockWidget, "GeoStationMultiviewDock")
    seen["dock_title"] = dock.windowTitle() if dock else None
    seen["views"] = sum(1 for i in range(6) if dock and dock.findChild(QObject, "mGeoStationImageView%d" % i) is not None
                        and dock.findChild(QObject, "mGeoStationImageView%d" % i).isVisible())
    seen["messages"] = message_bar_texts()
    return seen


def check():
    result = {}
    try:
        window = iface.mainWindow()
        menu = window.findChild(QMenu, "mGeoStationMenu")
        result["menu"] = menu is not None
        result["menu_title"] = menu.title() if menu else None
        result["menu_actions"] = [a.objectName() for a in menu.actions()] if menu else []
        toolbar = window.findChild(QToolBar, "mGeoStationToolBar")
        result["toolbar"] = toolbar is not None
        # each toolbar button's icon: drawn (not a null icon) and its own (the image's bytes)
        result["toolbar_icons"] = {}
        for action in (toolbar.actions() if toolbar else []):
            if action.isSeparator() or not action.objectName():
                continue
            image = action.icon().pixmap(32, 32).toImage()
            result["toolbar_icons"][action.objectName()] = None if image.isNull() else hashlib.sha1(bytes(image.constBits().asarray(image.sizeInBytes()))).hexdigest()
        guide = window.findChild(QAction, "mActionGeoStationUserGuide")
        result["user_guide_action"] = guide is not None and bool(guide.toolTip())
        result["provider_icon"] = not QgsApplication.processingRegistry().providerById("geostation").icon().isNull()
        adjustment = window.findChild(QMenu, "mGeoStationAdjustmentMenu")
        result["adjustment_actions"] = [a.objectName() for a in adjustment.actions()] if adjustment else []
        registry = QgsApplication.processingRegistry()
        result["provider"] = registry.providerById("geostation") is not None
        result["algorithm"] = registry.algorithmById("geostation:project_to_image") is not None
        result["algorithms"] = sorted(a.id() for a in registry.providerById("geostation").algorithms()) if result["provider"] else []

        plugin = window.findChild(QObject, "GeoStationPlugin")
        result["plugin_object"] = plugin is not None
        if plugin is not None:
            iface.messageBar().clearWidgets()
            result["bad_block_opened"] = open_block(plugin, BAD_BLOCK)
            result["bad_block_messages"] = message_bar_texts()
            iface.messageBar().clearWidgets()
            result["good_block_opened"] = open_block(plugin, GOOD_BLOCK)
            result["good_block_messages"] = message_bar_texts()
            result["block_info"] = show_block_info(window)
            result["resection_dialog"] = open_algorithm_dialog(window, "mActionGeoStationResection")
            iface.messageBar().clearWidgets()
            result["import_dialog"] = import_through_the_dialog(window)

        import processing
        output = processing.run("geostation:project_to_image", {
            "BLOCK": GOOD_BLOCK, "IMAGE": "S0002_front_right", "INPUT": OBJECTS, "OUTPUT": "TEMPORARY_OUTPUT"})
        result["processing_in_frame"] = output["IN_FRAME_COUNT"]

        window.showMaximized()
        QgsApplication.processEvents()
        result["screenshot"] = window.grab().save(SCREENSHOT)
    except Exception:  # reported to the driver, which fails the test
        result["exception"] = traceback.format_exc()
    with open(RESULT, "w") as f:
        json.dump(result, f, indent=2)
    QgsProject.instance().setDirty(False)
    iface.actionExit().trigger()


# Let QGIS finish starting (plugins, window) before looking.
QTimer.singleShot(3000, check)
