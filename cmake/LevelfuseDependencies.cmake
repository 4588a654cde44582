# Locate OpenVDB (Debian ships only its FindOpenVDB.cmake module), TBB and friends.

find_path(LEVELFUSE_OPENVDB_MODULE_DIR FindOpenVDB.cmake
  PATHS
    "/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB"
    "/usr/lib/cmake/OpenVDB"
    "/usr/local/lib/cmake/OpenVDB"
    "/usr/local/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB"
    "/usr/share/OpenVDB/cmake"
  DOC "Folder holding OpenVDB's FindOpenVDB.cmake")
if(LEVELFUSE_OPENVDB_MODULE_DIR)
  list(APPEND CMAKE_MODULE_PATH "${LEVELFUSE_OPENVDB_MODULE_DIR}")
endif()

# FindOpenVDB forces BUILD_SHARED_LIBS on; our targets state their type explicitly.
find_package(OpenVDB REQUIRED COMPONENTS openvdb)
find_package(TBB REQUIRED)
find_package(Threads REQUIRED)

# Depth images (16-bit PNG) and scan manifests (JSON); EXR depth images when
# OpenEXR is there.
find_package(PNG REQUIRED)
find_path(LEVELFUSE_JSON_INCLUDE_DIR nlohmann/json.hpp)
if(NOT LEVELFUSE_JSON_INCLUDE_DIR)
  message(FATAL_ERROR "nlohmann/json not found: install nlohmann-json3-dev (Debian)")
endif()
find_package(OpenEXR CONFIG QUIET)
if(TARGET OpenEXR::OpenEXR)
  set(LEVELFUSE_HAVE_OPENEXR ON)
  message(STATUS "levelfuse: OpenEXR ${OpenEXR_VERSION} found, EXR depth images enabled")
else()
  set(LEVELFUSE_HAVE_OPENEXR OFF)
  message(STATUS "levelfuse: OpenEXR not found, EXR depth images disabled")
endif()
