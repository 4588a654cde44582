# Install the library, headers and an exported CMake package so that other
# projects can `find_package(levelfuse)` and link `levelfuse::levelfuse`.

include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(LEVELFUSE_CMAKE_INSTALL_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/levelfuse")

install(TARGETS levelfuse EXPORT levelfuseTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY include/levelfuse DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES "${PROJECT_BINARY_DIR}/include/levelfuse/Version.h"
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/levelfuse)
install(EXPORT levelfuseTargets NAMESPACE levelfuse:: DESTINATION ${LEVELFUSE_CMAKE_INSTALL_DIR})

configure_package_config_file(cmake/levelfuseConfig.cmake.in
  "${PROJECT_BINARY_DIR}/levelfuseConfig.cmake"
  INSTALL_DESTINATION ${LEVELFUSE_CMAKE_INSTALL_DIR})
write_basic_package_version_file("${PROJECT_BINARY_DIR}/levelfuseConfigVersion.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES
  "${PROJECT_BINARY_DIR}/levelfuseConfig.cmake"
  "${PROJECT_BINARY_DIR}/levelfuseConfigVersion.cmake"
  DESTINATION ${LEVELFUSE_CMAKE_INSTALL_DIR})
