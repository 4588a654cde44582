# Where OpenVDB's FindOpenVDB.cmake lives: Debian ships OpenVDB with that find
# module and no package configuration. Included by levelfuse's build and by its
# installed package configuration, so a consumer finds OpenVDB the same way;
# set LEVELFUSE_OPENVDB_MODULE_DIR to use a module elsewhere.

if(NOT LEVELFUSE_OPENVDB_MODULE_DIR)
  find_path(LEVELFUSE_OPENVDB_MODULE_DIR FindOpenVDB.cmake
    PATHS
      "/usr/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB"
      "/usr/lib/cmake/OpenVDB"
      "/usr/local/lib/cmake/OpenVDB"
      "/usr/local/lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/OpenVDB"
      "/usr/share/OpenVDB/cmake"
    DOC "Folder holding OpenVDB's FindOpenVDB.cmake")
endif()
if(LEVELFUSE_OPENVDB_MODULE_DIR)
  list(APPEND CMAKE_MODULE_PATH "${LEVELFUSE_OPENVDB_MODULE_DIR}")
endif()
