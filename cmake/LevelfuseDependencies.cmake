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
