# Helpers for the tests.
#
# geostation_test_tool_missing(<sentence>)
#   A program or data package some tests need is missing: a warning (the
#   tests are left out), or with GEOSTATION_REQUIRE_TEST_TOOLS (CI) an error.
function(geostation_test_tool_missing sentence)
  if(GEOSTATION_REQUIRE_TEST_TOOLS)
    message(FATAL_ERROR "${sentence} (GEOSTATION_REQUIRE_TEST_TOOLS is on: scripts/setup-debian.sh installs everything the tests need)")
  else()
    message(WARNING "${sentence}")
  endif()
endfunction()

# Helpers for the Qt-based tests (provider, GUI, benchmarks that need Qt).
#
# geostation_add_qt_test(<test name> <executable target> <label> [TIMEOUT <s>])
#   Registers an offscreen QtTest executable. Every test gets a HOME of its
#   own below the build folder, so QGIS' profile and settings files of two
#   tests never meet when CTest runs them in parallel (ctest -j). QtTest's and
#   QGIS's headers, most of each test program's compile time, are
#   precompiled once: for the first program registered, reused by the others.
function(geostation_add_qt_test name target label)
  cmake_parse_arguments(ARG "" "TIMEOUT" "" ${ARGN})
  get_property(pch_owner GLOBAL PROPERTY GEOSTATION_QT_TEST_PCH_OWNER)
  if(NOT pch_owner)
    target_precompile_headers(${target} PRIVATE
      <QtTest/QtTest> <QTemporaryDir> <QJsonDocument> <QJsonObject> <QJsonArray> <qgsapplication.h> <qgsproject.h>
      <qgsvectorlayer.h> <qgsrasterlayer.h> <qgsprocessingregistry.h> <qgsprocessingcontext.h> <qgsprocessingalgorithm.h>
      <qgsprocessingfeedback.h> <qgsgeometry.h> <qgslinestring.h> <qgsfeatureiterator.h> <gdal.h>
      <functional> <memory> <optional> <string> <vector>)
    set_property(GLOBAL PROPERTY GEOSTATION_QT_TEST_PCH_OWNER ${target})
  elseif(NOT pch_owner STREQUAL target)
    target_precompile_headers(${target} REUSE_FROM ${pch_owner})
  endif()
  set(home "${CMAKE_CURRENT_BINARY_DIR}/home-${name}")
  file(MAKE_DIRECTORY "${home}")
  add_test(NAME ${name} COMMAND ${target})
  set_tests_properties(${name} PROPERTIES LABELS ${label}
    ENVIRONMENT "QT_QPA_PLATFORM=offscreen;HOME=${home};XDG_RUNTIME_DIR=${home}")
  if(ARG_TIMEOUT)
    set_tests_properties(${name} PROPERTIES TIMEOUT ${ARG_TIMEOUT})
  endif()
endfunction()
