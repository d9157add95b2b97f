# The installed tree works on its own: geostation-simulate runs from bin/
# without LD_LIBRARY_PATH (its RPATH finds lib/), geostation-batch from bin/
# with its package beside it, the bridge's metadata carries
# the project's version, and installing into a QGIS profile twice swaps the
# old installation out without leaving it behind.
#   cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DVERSION=... -P checkinstalltree.cmake
file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${prefix}" RESULT_VARIABLE rc OUTPUT_QUIET)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "cmake --install failed (${rc})")
endif()

# the simulator from the installed tree, with nothing on the library path
execute_process(COMMAND env -u LD_LIBRARY_PATH "${prefix}/bin/geostation-simulate" --help RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "usage: geostation-simulate")
  message(FATAL_ERROR "the installed geostation-simulate does not run (${rc}): ${err}")
endif()

# the batch command from the installed tree (its package beside it)
execute_process(COMMAND "${prefix}/bin/geostation-batch" --help RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(NOT rc EQUAL 0 OR NOT out MATCHES "usage: geostation-batch")
  message(FATAL_ERROR "the installed geostation-batch does not run (${rc}): ${err}")
endif()

# the version, defined once in project(), reaches the bridge's metadata
file(STRINGS "${prefix}/python/geostation_processing/metadata.txt" versionLine REGEX "^version=")
if(NOT versionLine STREQUAL "version=${VERSION}")
  message(FATAL_ERROR "the installed metadata says '${versionLine}', the project ${VERSION}")
endif()

# installing over an installation: one plugin folder, one bridge, nothing left aside
set(profile "${WORK_DIR}/profile")
foreach(round 1 2)
  execute_process(COMMAND "${SOURCE_DIR}/scripts/install-plugin.sh" --build-dir "${BUILD_DIR}" --profile-dir "${profile}"
    RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "install-plugin.sh failed in round ${round} (${rc}): ${err}")
  endif()
endforeach()
file(GLOB leftovers LIST_DIRECTORIES true "${profile}/.geostation-*")
if(leftovers)
  message(FATAL_ERROR "install-plugin.sh left ${leftovers} behind")
endif()
foreach(expected geostation/plugins/libgeostationplugin.so geostation/lib/libgeostation_processing.so python/plugins/geostation_processing/metadata.txt)
  if(NOT EXISTS "${profile}/${expected}")
    message(FATAL_ERROR "after installing twice, ${expected} is missing from the profile")
  endif()
endforeach()
file(REMOVE_RECURSE "${WORK_DIR}")
