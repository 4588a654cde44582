# Locate OpenVDB (Debian ships only its FindOpenVDB.cmake module), TBB and friends.

include(levelfuseOpenVDBModule)

# FindOpenVDB forces BUILD_SHARED_LIBS on; our targets state their type explicitly.
find_package(OpenVDB REQUIRED COMPONENTS openvdb)
find_package(TBB REQUIRED)
find_package(Threads REQUIRED)
# Packed range maps (scan/PackedRangeMap.h) compress with Zstandard (libzstd-dev,
# which installs its CMake package).
find_package(zstd CONFIG QUIET)
if(NOT TARGET zstd::libzstd_shared)
  message(FATAL_ERROR "Zstandard not found: install libzstd-dev (Debian)")
endif()

# Depth images (16-bit PNG), scan manifests (JSON) and E57 files (XML); EXR depth images when
# OpenEXR is there.
find_package(PNG REQUIRED)
# E57 files' XML section.
find_package(pugixml CONFIG QUIET)
if(NOT TARGET pugixml::pugixml)
  message(FATAL_ERROR "pugixml not found: install libpugixml-dev (Debian)")
endif()
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

# MPI (OpenMPI from Debian): the reconstruction shared by processes (mpi/).
# Optional; left out of sanitizer builds, whose leak checks MPI's own
# allocations would trip.
option(LEVELFUSE_MPI "Build the MPI layer (levelfuse_mpi) when MPI is found (not under a sanitizer)" ON)
set(LEVELFUSE_HAVE_MPI OFF)
if(LEVELFUSE_MPI AND NOT LEVELFUSE_SANITIZER)
  find_package(MPI COMPONENTS CXX QUIET)
  if(MPI_CXX_FOUND)
    set(LEVELFUSE_HAVE_MPI ON)
    message(STATUS "levelfuse: MPI ${MPI_CXX_VERSION} found, the MPI layer is built")
  else()
    message(STATUS "levelfuse: MPI not found (libopenmpi-dev), the MPI layer is left out")
  endif()
endif()
