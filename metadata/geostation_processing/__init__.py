"""Bridge that registers GeoStation's C++ Processing provider.

qgis_process loads only Python plugins with ``hasProcessingProvider=yes``.
This plugin loads ``libgeostation_processing.so`` with ctypes and calls its
exported ``geostation_register_provider()``; the library registers the
``geostation`` provider with QGIS's processing registry (idempotently).

The library is looked for, in order:
  1. ``$GEOSTATION_PROVIDER_LIBRARY``;
  2. ``<profile>/geostation/lib/libgeostation_processing.so`` (what
     scripts/install-plugin.sh installs), this file being in
     ``<profile>/python/plugins/geostation_processing/``.
"""

import ctypes
import os

LIBRARY_NAME = "libgeostation_processing.so"


def provider_library_path():
    override = os.environ.get("GEOSTATION_PROVIDER_LIBRARY")
    if override:
        return override
    here = os.path.dirname(os.path.abspath(__file__))
    profile = os.path.normpath(os.path.join(here, "..", "..", ".."))
    return os.path.join(profile, "geostation", "lib", LIBRARY_NAME)


class GeoStationProcessingBridge:
    def __init__(self, iface=None):
        self.iface = iface
        self.library = None
        self.registered = False

    def initProcessing(self):
        from qgis.core import Qgis, QgsMessageLog

        path = provider_library_path()
        if not os.path.exists(path):
            QgsMessageLog.logMessage(
                "GeoStation provider library not found at {}; run scripts/install-plugin.sh".format(path),
                "GeoStation", Qgis.Critical)
            return
        try:
            self.library = ctypes.CDLL(path)
            self.registered = bool(self.library.geostation_register_provider())
        except (OSError, AttributeError) as error:
            QgsMessageLog.logMessage(
                "GeoStation provider library {} could not be loaded: {}".format(path, error),
                "GeoStation", Qgis.Critical)

    def initGui(self):
        self.initProcessing()

    def unload(self):
        if self.library is not None and self.registered:
            self.library.geostation_unregister_provider()
            self.registered = False


def classFactory(iface):
    return GeoStationProcessingBridge(iface)
