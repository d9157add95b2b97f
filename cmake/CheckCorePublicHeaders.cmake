# Fails when a public header of core/ includes Ceres or nlohmann::json:
# headers that expose them live in a module's internal/ folder, which only
# that module's sources (and the tests) see, so the public headers of core -
# what the provider, the plugin and the benchmarks include - stay free of
# both. (Which module may include which the compiler decides: every module
# has an include root of its own, core/CMakeLists.txt.)
#   cmake -DCORE_DIR=<core> -P CheckCorePublicHeaders.cmake
file(GLOB_RECURSE headers RELATIVE "${CORE_DIR}" "${CORE_DIR}/*.h" "${CORE_DIR}/*.hpp")
set(offenders "")
set(checked 0)
foreach(header ${headers})
  if(header MATCHES "/internal/" OR NOT header MATCHES "/")
    continue()
  endif()
  math(EXPR checked "${checked} + 1")
  string(REGEX MATCH "^[^/]+" module "${header}")
  file(STRINGS "${CORE_DIR}/${header}" private REGEX "^[ \t]*#[ \t]*include[ \t]*[<\"](ceres/|nlohmann/)")
  foreach(line ${private})
    string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]*" "" line "${line}")
    list(APPEND offenders "${header} is a public header and includes ${line}: move it to ${module}/internal/")
  endforeach()
endforeach()
if(offenders)
  string(REPLACE ";" "\n  " report "${offenders}")
  message(FATAL_ERROR "core/'s public headers do not include Ceres or nlohmann::json (docs/architecture.md):\n  ${report}")
endif()
message(STATUS "core's public headers: ${checked} checked, none includes Ceres or nlohmann::json")
