"""Helpers for the scripts that run inside QGIS desktop (qgis.bin --code):
waiting while QGIS works, calling the plugin's slots, writing what was found
so far, and quitting with every question QGIS asks at exit recorded and
answered. desktop_harness.run_qgis() puts this folder on the script's path
(GEOSTATION_E2E_SCRIPTS)."""

import json
import time

from qgis.core import QgsApplication, QgsProject
from qgis.PyQt.QtCore import Q_ARG, Q_RETURN_ARG, QMetaObject, Qt, QTimer
from qgis.utils import iface


def wait(seconds):
    end = time.time() + seconds
    while time.time() < end:
        QgsApplication.processEvents()
        time.sleep(0.01)


def invoke(obj, name, *args, returns=None):
    qargs = [Q_ARG(type(a), a) for a in args]
    if returns is not None:
        return QMetaObject.invokeMethod(obj, name, Qt.DirectConnection, Q_RETURN_ARG(returns), *qargs)
    return QMetaObject.invokeMethod(obj, name, Qt.DirectConnection, *qargs)


def checkpoint(result, path, stage):
    """Writes what is known so far, so a hang shows where it happened."""
    result["stage"] = stage
    with open(path, "w") as f:
        json.dump(result, f, indent=2)


def finish(result, path, answer=None):
    """Writes the result and quits QGIS. A dialog at exit is recorded in the result's `exit_dialogs`;
    `answer(text)` may name the QMessageBox button to press for it (e.g. QMessageBox.Save), else it is
    rejected."""
    with open(path, "w") as f:
        json.dump(result, f, indent=2)
    QgsProject.instance().setDirty(False)

    def modal_at_exit():
        from qgis.PyQt.QtWidgets import QApplication, QMessageBox
        dialog = QApplication.activeModalWidget()
        if dialog is None:
            return
        text = dialog.text() if isinstance(dialog, QMessageBox) else dialog.windowTitle()
        with open(path) as f:
            saved = json.load(f)
        saved.setdefault("exit_dialogs", []).append(text)
        with open(path, "w") as f:
            json.dump(saved, f, indent=2)
        button = answer(text) if answer else None
        if button is not None and isinstance(dialog, QMessageBox) and dialog.button(button) is not None:
            dialog.button(button).click()
        else:
            dialog.reject()
        QTimer.singleShot(2000, modal_at_exit)

    QTimer.singleShot(3000, modal_at_exit)
    iface.actionExit().trigger()
