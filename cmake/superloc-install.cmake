# Install layout and the CMake package (find_package(superloc) from another project):
#   bin/superloc-*                      apps
#   lib/libsuperloc_<module>.a          one static library per module (superloc::<module>)
#   include/superloc/<module>/*.h       public headers
#   share/superloc/ini/                 INI presets (localize.ini, sensors/, sim/, bench/)
#   lib/cmake/superloc/                 superloc-config.cmake, -config-version.cmake, -targets.cmake
include(CMakePackageConfigHelpers)

set(SUPERLOC_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/superloc)
set(SUPERLOC_INSTALL_INIDIR ${CMAKE_INSTALL_DATADIR}/superloc/ini)
# Read by superloc-config.cmake.in: optional modules whose dependencies the consumer must find.
if(TARGET superloc_sim)
  set(SUPERLOC_WITH_SIM ON)
else()
  set(SUPERLOC_WITH_SIM OFF)
endif()

install(DIRECTORY ${PROJECT_SOURCE_DIR}/ini/ DESTINATION ${SUPERLOC_INSTALL_INIDIR} COMPONENT data)
install(FILES ${PROJECT_SOURCE_DIR}/LICENSE ${PROJECT_SOURCE_DIR}/README.md
  DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/superloc COMPONENT data)

install(EXPORT superloc-targets NAMESPACE superloc:: DESTINATION ${SUPERLOC_INSTALL_CMAKEDIR}
  COMPONENT dev)
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/superloc-config.cmake.in
  ${PROJECT_BINARY_DIR}/superloc-config.cmake
  INSTALL_DESTINATION ${SUPERLOC_INSTALL_CMAKEDIR}
  PATH_VARS SUPERLOC_INSTALL_INIDIR)
# 0.x: minor versions may break the interface.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/superloc-config-version.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/superloc-config.cmake
  ${PROJECT_BINARY_DIR}/superloc-config-version.cmake
  DESTINATION ${SUPERLOC_INSTALL_CMAKEDIR} COMPONENT dev)
