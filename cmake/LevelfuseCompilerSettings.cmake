# Warnings, ccache and sanitizers for levelfuse's own targets.

find_program(LEVELFUSE_CCACHE ccache)
if(LEVELFUSE_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  # ccache caches a source built with a precompiled header only when told to
  # overlook the header's defines and time macros (its manual, "Precompiled headers").
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env CCACHE_SLOPPINESS=pch_defines,time_macros
      "${LEVELFUSE_CCACHE}")
  set(CMAKE_C_COMPILER_LAUNCHER "${LEVELFUSE_CCACHE}")
endif()

# The OpenVDB grids and trees levelfuse leaves to libopenvdb to instantiate
# (src/core/OpenVdbInstantiations.h): the first header of every levelfuse source,
# in the precompiled headers, and otherwise through levelfuse_openvdb_instantiations.
set(LEVELFUSE_OPENVDB_INSTANTIATIONS "${PROJECT_SOURCE_DIR}/src/core/OpenVdbInstantiations.h")

# levelfuse_openvdb_instantiations(<target>): includes that header first in
# each of <target>'s sources, for a target without a precompiled header.
function(levelfuse_openvdb_instantiations target)
  target_compile_options(${target} PRIVATE -include "${LEVELFUSE_OPENVDB_INSTANTIATIONS}")
endfunction()

# levelfuse_unity_build(<target> <sources per batch>): compiles <target>'s sources in
# batches, each one translation unit. Most sources include OpenVDB's headers, and a
# batch parses them and instantiates their templates once rather than once a source
# (docs/BUILD.md). Off with -DLEVELFUSE_UNITY_BUILD=OFF, where one source is edited
# and rebuilt again and again.
function(levelfuse_unity_build target batch_size)
  if(LEVELFUSE_UNITY_BUILD)
    set_target_properties(${target} PROPERTIES UNITY_BUILD ON UNITY_BUILD_MODE BATCH
                          UNITY_BUILD_BATCH_SIZE ${batch_size})
  endif()
endfunction()

# levelfuse_optimise_less(<target>): -O2 rather than Release's -O3, for code that does
# none of the reconstruction's work itself (the converter's commands, the Python
# bindings): GCC spends about a quarter less time on it, and the library it calls
# keeps -O3 (docs/BUILD.md). Sanitizer builds keep their own level.
function(levelfuse_optimise_less target)
  levelfuse_optimise_at(${target} -O2)
endfunction()

# levelfuse_optimise_tests(<target>): -O1 for the tests and their helpers, which
# check what the library (-O3) works out: GCC takes about half the time on them
# that it takes at -O2 (docs/BUILD.md). Sanitizer builds keep their own level.
function(levelfuse_optimise_tests target)
  levelfuse_optimise_at(${target} -O1)
endfunction()

# levelfuse_optimise_at(<target> <level>): <level> instead of Release's -O3.
function(levelfuse_optimise_at target level)
  if(NOT LEVELFUSE_SANITIZER)
    target_compile_options(${target} PRIVATE $<$<CONFIG:Release>:${level}>)
  endif()
endfunction()

# levelfuse_warnings(<target>): -Wall -Wextra for our code. OpenVDB, TBB and ITK
# headers are included as system headers, so their warnings stay out of the way.
# (clang, used for the fuzzers, spells GCC's -Wshadow=local as -Wshadow.)
function(levelfuse_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic
    $<IF:$<CXX_COMPILER_ID:GNU>,-Wshadow=local,-Wshadow>)
endfunction()

# The ASan+UBSan build is optimised with -O1 and leaves out UBSan's alignment
# and null checks: with them, at -O3, GCC 12 takes 5x as long on the engine's
# sources (SparseField.cc: 330 s against 88 s; plain -O3 52 s). ASan reports a
# null access itself; the fuzzers' clang build of the readers keeps every check.
if(LEVELFUSE_SANITIZER STREQUAL "address")
  set(_lf_san -fsanitize=address,undefined -fno-sanitize=alignment,null -fno-sanitize-recover=undefined
              -fno-omit-frame-pointer)
  set(_lf_san_optimisation -O1)
elseif(LEVELFUSE_SANITIZER STREQUAL "thread")
  set(_lf_san -fsanitize=thread -fno-omit-frame-pointer)
elseif(NOT LEVELFUSE_SANITIZER STREQUAL "")
  message(FATAL_ERROR "LEVELFUSE_SANITIZER must be '', 'address' or 'thread', not '${LEVELFUSE_SANITIZER}'")
endif()
# Instrument everything built here; the library also passes the link flags on
# to its users, who need the sanitizer runtimes to link against it.
set(LEVELFUSE_SANITIZER_FLAGS ${_lf_san})
if(_lf_san)
  add_compile_options(${_lf_san} ${_lf_san_optimisation})
  add_link_options(${_lf_san})
endif()
# Internal invariants (core/DebugCheck.h) are checked where bugs are hunted: the
# sanitizer builds and Debug builds.
if(_lf_san)
  add_compile_definitions(LEVELFUSE_DEBUG_CHECKS)
endif()
add_compile_definitions($<$<CONFIG:Debug>:LEVELFUSE_DEBUG_CHECKS>)
