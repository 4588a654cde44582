# Install the library, headers, an exported CMake package (find_package(levelfuse),
# target levelfuse::levelfuse; with MPI, the component mpi and its target
# levelfuse::mpi) and a pkg-config file (levelfuse.pc, the library alone), all
# relocatable: nothing in them names the machine levelfuse was built on.

include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(LEVELFUSE_CMAKE_INSTALL_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/levelfuse")

install(TARGETS levelfuse EXPORT levelfuseTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The MPI layer (include/levelfuse/mpi, levelfuse_mpi) is installed when it was built.
if(LEVELFUSE_HAVE_MPI)
  install(TARGETS levelfuse_mpi EXPORT levelfuseTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/levelfuse DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} PATTERN "*.in" EXCLUDE)
else()
  install(DIRECTORY include/levelfuse DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} PATTERN "*.in" EXCLUDE
          PATTERN "mpi" EXCLUDE)
endif()
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
  "${PROJECT_SOURCE_DIR}/cmake/levelfuseOpenVDBModule.cmake"
  DESTINATION ${LEVELFUSE_CMAKE_INSTALL_DIR})

# pkg-config: the prefix found from the file's own folder. A static levelfuse
# brings the libraries it links privately (its readers', Zstandard for packed
# range maps) into the consumer's link.
set(_lf_pc_dir "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
file(RELATIVE_PATH LEVELFUSE_PC_PREFIX_FROM_PCDIR "/prefix/${_lf_pc_dir}" "/prefix")
string(REGEX REPLACE "/$" "" LEVELFUSE_PC_PREFIX_FROM_PCDIR "${LEVELFUSE_PC_PREFIX_FROM_PCDIR}")
set(_lf_pc_readers " libpng libzstd pugixml")
if(LEVELFUSE_HAVE_OPENEXR)
  string(APPEND _lf_pc_readers " OpenEXR")
endif()
if(LEVELFUSE_SHARED)
  set(LEVELFUSE_PC_REQUIRES "")
  set(LEVELFUSE_PC_REQUIRES_PRIVATE "${_lf_pc_readers}")
else()
  set(LEVELFUSE_PC_REQUIRES "${_lf_pc_readers}")
  set(LEVELFUSE_PC_REQUIRES_PRIVATE "")
endif()
# A sanitizer build's users link its runtimes (LevelfuseCompilerSettings.cmake).
string(JOIN " " LEVELFUSE_PC_LINK_FLAGS ${LEVELFUSE_SANITIZER_FLAGS})
configure_file(cmake/levelfuse.pc.in "${PROJECT_BINARY_DIR}/levelfuse.pc" @ONLY)
install(FILES "${PROJECT_BINARY_DIR}/levelfuse.pc" DESTINATION ${_lf_pc_dir})
