# Warnings, ccache and sanitizers for levelfuse's own targets.

find_program(LEVELFUSE_CCACHE ccache)
if(LEVELFUSE_CCACHE AND NOT CMAKE_CXX_COMPILER_LAUNCHER)
  # ccache caches a source built with a precompiled header only when told to
  # overlook the header's defines and time macros (its manual, "Precompiled headers").
  set(CMAKE_CXX_COMPILER_LAUNCHER ${CMAKE_COMMAND} -E env CCACHE_SLOPPINESS=pch_defines,time_macros
      "${LEVELFUSE_CCACHE}")
  set(CMAKE_C_COMPILER_LAUNCHER "${LEVELFUSE_CCACHE}")
endif()

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
