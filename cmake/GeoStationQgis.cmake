# QGIS's libraries as imported targets (qgis::core, qgis::analysis, qgis::gui)
# and Qt, shared by the Processing provider (processing/) and the desktop
# plugin (plugin/), each configurable on its own. Included by each: Qt's
# imported targets belong to the directory that finds them, QGIS's are global.
find_package(Qt5 5.15 REQUIRED COMPONENTS Core Gui Widgets Xml Svg Concurrent)
# Debian's libqgis-dev ships FindQGIS.cmake in /usr/share/qgis.
list(APPEND CMAKE_MODULE_PATH /usr/share/qgis)
find_package(QGIS REQUIRED)

if(TARGET qgis::core)
  return()
endif()
# QGIS's headers as an imported target.
add_library(qgis::core INTERFACE IMPORTED GLOBAL)
set_target_properties(qgis::core PROPERTIES
  INTERFACE_INCLUDE_DIRECTORIES "${QGIS_INCLUDE_DIR}"
  INTERFACE_LINK_LIBRARIES "${QGIS_CORE_LIBRARY};Qt5::Core;Qt5::Gui;Qt5::Widgets;Qt5::Xml")
add_library(qgis::analysis INTERFACE IMPORTED GLOBAL)
set_target_properties(qgis::analysis PROPERTIES INTERFACE_LINK_LIBRARIES "${QGIS_ANALYSIS_LIBRARY};qgis::core")
add_library(qgis::gui INTERFACE IMPORTED GLOBAL)
set_target_properties(qgis::gui PROPERTIES INTERFACE_LINK_LIBRARIES "${QGIS_GUI_LIBRARY};qgis::core;Qt5::Svg")
