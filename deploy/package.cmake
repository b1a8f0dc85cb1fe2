# Install layout and the Debian package (docs/operations.md, "Installing
# the package"). In the build folder, after building the thermocomp target:
#   cpack -G DEB      ->  thermocomp_<version>_amd64.deb
# The package puts the program in /usr/bin, the configuration in
# /etc/thermocomp (conffiles), the systemd unit in /lib/systemd/system
# (Debian 12 keeps units there) and the data in /var/lib/thermocomp, which
# its postinst creates for the system user "thermocomp". The OPC UA face
# goes to /usr/share/thermocomp/opcua with the node-opcua tree
# deploy/opcua-deps.sh installed (npm ci, before cpack), and its unit
# beside the server's, installed but not enabled.

set(THERMOCOMP_PACKAGE_PREFIX /usr)
set(THERMOCOMP_INSTALLED_BINARY ${THERMOCOMP_PACKAGE_PREFIX}/bin/thermocomp)
set(THERMOCOMP_CONFIG_DIR /etc/thermocomp)
set(THERMOCOMP_STATE_DIR /var/lib/thermocomp)

# The build's description for `thermocomp --version`, taken now: a commit
# made later shows after the next configure.
set(THERMOCOMP_GIT_DESCRIBE "")
find_package(Git QUIET)
if(GIT_FOUND AND EXISTS ${PROJECT_SOURCE_DIR}/.git)
  execute_process(COMMAND ${GIT_EXECUTABLE} describe --always --dirty
                  WORKING_DIRECTORY ${PROJECT_SOURCE_DIR}
                  OUTPUT_VARIABLE THERMOCOMP_GIT_DESCRIBE OUTPUT_STRIP_TRAILING_WHITESPACE
                  ERROR_QUIET RESULT_VARIABLE git_result)
  if(NOT git_result EQUAL 0)
    set(THERMOCOMP_GIT_DESCRIBE "")
  endif()
endif()
configure_file(${PROJECT_SOURCE_DIR}/core/version.h.in
               ${CMAKE_BINARY_DIR}/generated/core/version.h @ONLY)
# The services report it too (thermocomp_build_info on /metrics), and
# everything above them sees it through theirs.
target_include_directories(thermocomp_service PUBLIC ${CMAKE_BINARY_DIR}/generated)

# The installed configuration is deploy/thermocomp.toml with its relative
# paths (the development layout) made the package's absolute ones.
set(shipped_toml ${PROJECT_SOURCE_DIR}/deploy/thermocomp.toml)
set_property(DIRECTORY APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS ${shipped_toml})
file(READ ${shipped_toml} installed_toml)
string(REGEX REPLACE "\npath = \"[^\"/][^\"]*\"" "\npath = \"${THERMOCOMP_STATE_DIR}/thermocomp.db\""
       installed_toml "${installed_toml}")
string(REGEX REPLACE "\nconfig = \"[^\"/][^\"]*\"" "\nconfig = \"${THERMOCOMP_CONFIG_DIR}/cyclonedds.xml\""
       installed_toml "${installed_toml}")
file(WRITE ${CMAKE_BINARY_DIR}/package/thermocomp.toml "${installed_toml}")

install(TARGETS thermocomp RUNTIME DESTINATION bin)
# The file may hold access tokens: root and the service's group read it
# (postinst sets the group).
install(FILES ${CMAKE_BINARY_DIR}/package/thermocomp.toml DESTINATION ${THERMOCOMP_CONFIG_DIR}
        PERMISSIONS OWNER_READ OWNER_WRITE GROUP_READ)
install(FILES ${PROJECT_SOURCE_DIR}/deploy/cyclonedds.xml DESTINATION ${THERMOCOMP_CONFIG_DIR})
install(FILES ${PROJECT_SOURCE_DIR}/deploy/thermocomp.service
              ${PROJECT_SOURCE_DIR}/deploy/thermocomp-opcua.service
        DESTINATION /lib/systemd/system)
# The OPC UA face (docs/opcua.md): the program, its sources and its
# dependencies exactly as opcua/package-lock.json pins them, run by node
# (Depends: nodejs). Its node_modules are plain JavaScript (no native
# module), so the tree is the same on every architecture.
set(opcua_dir ${PROJECT_SOURCE_DIR}/opcua)
install(CODE "
  if(NOT EXISTS \"${opcua_dir}/node_modules/.package-lock.json\")
    message(FATAL_ERROR \"opcua/node_modules is missing or incomplete: run deploy/opcua-deps.sh before cpack\")
  endif()")
install(FILES ${opcua_dir}/thermocomp-opcua.js ${opcua_dir}/package.json ${opcua_dir}/package-lock.json
        DESTINATION share/thermocomp/opcua)
install(DIRECTORY ${opcua_dir}/src ${opcua_dir}/nodeset DESTINATION share/thermocomp/opcua)
# Without the TypeScript sources, declarations and source maps node never
# loads: 4 000 of its 6 400 files, 30 of its 47 MB.
install(DIRECTORY ${opcua_dir}/node_modules DESTINATION share/thermocomp/opcua
        PATTERN "*.map" EXCLUDE PATTERN "*.ts" EXCLUDE PATTERN "*.mts" EXCLUDE PATTERN "*.cts" EXCLUDE)
# operations.md and the unit send the administrator to opcua.md for the
# face's trust and certificate users.
install(FILES ${PROJECT_SOURCE_DIR}/README.md ${PROJECT_SOURCE_DIR}/docs/operations.md
              ${PROJECT_SOURCE_DIR}/docs/opcua.md
        DESTINATION share/doc/thermocomp)
# What the plant's other services take from it: the TLS proxy's
# configuration, the Prometheus rules and scrape example, the Grafana
# dashboard (docs/operations.md, Exposure and TLS, Alerts).
install(FILES ${PROJECT_SOURCE_DIR}/deploy/nginx/thermocomp.conf
        DESTINATION share/doc/thermocomp/examples/nginx)
install(FILES ${PROJECT_SOURCE_DIR}/deploy/prometheus/thermocomp-rules.yml
              ${PROJECT_SOURCE_DIR}/deploy/prometheus/prometheus.yml
        DESTINATION share/doc/thermocomp/examples/prometheus)
install(FILES ${PROJECT_SOURCE_DIR}/deploy/grafana/thermocomp.json
        DESTINATION share/doc/thermocomp/examples/grafana)

# cpack installs what is built; it does not build every target first (the
# tests and benchmarks take half an hour on two cores): build `thermocomp`,
# then run cpack.
set(CMAKE_SKIP_INSTALL_ALL_DEPENDENCY ON)

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME thermocomp)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGING_INSTALL_PREFIX ${THERMOCOMP_PACKAGE_PREFIX})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "thermal compensation server for CNC machine tools")
set(CPACK_PACKAGE_DESCRIPTION
    "Archives machine temperatures and probe measurements, fits a thermal-error model per axis and serves the compensation each control should apply, over HTTP, DDS and OPC UA.")
set(THERMOCOMP_PACKAGE_MAINTAINER "thermocomp maintainers <thermocomp@localhost>"
    CACHE STRING "Maintainer field of the Debian package")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER ${THERMOCOMP_PACKAGE_MAINTAINER})
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_PACKAGE_PRIORITY optional)
# The shared libraries' packages come from dpkg-shlibdeps (dpkg-dev), run on
# the binary when cpack packs (deploy/package-depends.cmake says why not by
# CPACK_DEBIAN_PACKAGE_SHLIBDEPS); the rest is what the program reads or
# its scripts call: the charting library of the pages, the zone database,
# adduser for the user, procps for the unit's ExecReload (/bin/kill), and
# node for the OPC UA face (Debian 12's nodejs is 18.19; a newer one from
# NodeSource satisfies it too).
file(GENERATE OUTPUT ${CMAKE_BINARY_DIR}/package/binary-path.txt CONTENT "$<TARGET_FILE:thermocomp>")
set(CPACK_THERMOCOMP_BINARY_FILE ${CMAKE_BINARY_DIR}/package/binary-path.txt)
set(CPACK_THERMOCOMP_PACKAGE_WORK ${CMAKE_BINARY_DIR}/package)
set(CPACK_PROJECT_CONFIG_FILE ${PROJECT_SOURCE_DIR}/deploy/package-depends.cmake)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "adduser, libjs-dygraphs, procps, tzdata, nodejs (>= 18.19)")
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    ${PROJECT_SOURCE_DIR}/deploy/debian/conffiles ${PROJECT_SOURCE_DIR}/deploy/debian/postinst
    ${PROJECT_SOURCE_DIR}/deploy/debian/prerm ${PROJECT_SOURCE_DIR}/deploy/debian/postrm)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
include(CPack)
