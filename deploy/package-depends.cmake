# Read by cpack (CPACK_PROJECT_CONFIG_FILE, deploy/package.cmake) when it
# packs: the packages of the shared libraries the built program needs,
# from dpkg-shlibdeps run on that one binary, ahead of the Depends the
# project names. CPack's own CPACK_DEBIAN_PACKAGE_SHLIBDEPS would start
# `file` once per packaged file to find the binaries first: the OPC UA
# face's node_modules are some 6 000 files, and that scan took most of
# three minutes of every package build.
if(NOT CPACK_GENERATOR STREQUAL "DEB")
  return()
endif()
file(READ "${CPACK_THERMOCOMP_BINARY_FILE}" thermocomp_binary)
find_program(THERMOCOMP_SHLIBDEPS dpkg-shlibdeps)
if(NOT THERMOCOMP_SHLIBDEPS)
  message(FATAL_ERROR "dpkg-shlibdeps (dpkg-dev) is missing: it finds the packages of the program's shared libraries")
endif()
# dpkg-shlibdeps wants a source package's debian/control where it runs.
set(shlibdeps_dir "${CPACK_THERMOCOMP_PACKAGE_WORK}/shlibdeps")
file(REMOVE_RECURSE "${shlibdeps_dir}")
file(WRITE "${shlibdeps_dir}/debian/control" "")
execute_process(COMMAND ${CMAKE_COMMAND} -E env LC_ALL=C ${THERMOCOMP_SHLIBDEPS} -O "${thermocomp_binary}"
                WORKING_DIRECTORY "${shlibdeps_dir}"
                RESULT_VARIABLE shlibdeps_result OUTPUT_VARIABLE shlibdeps_out ERROR_VARIABLE shlibdeps_err)
if(NOT shlibdeps_result EQUAL 0 OR NOT shlibdeps_out MATCHES "shlibs:Depends=([^\n]+)")
  message(FATAL_ERROR "dpkg-shlibdeps -O ${thermocomp_binary} failed: ${shlibdeps_err}")
endif()
set(CPACK_DEBIAN_PACKAGE_DEPENDS "${CMAKE_MATCH_1}, ${CPACK_DEBIAN_PACKAGE_DEPENDS}")
