# The installed package as a new user meets it, following the README: installs
# the build tree into a scratch prefix, then
#  1. checks that the install names no folder of this machine outside the
#     prefix and holds no template (*.in), and that levelfuse/levelfuse.h
#     includes every public header;
#  2. builds the README's consumer (its CMakeLists.txt and main.cpp, taken from
#     the README's text) against the prefix with warnings as errors, and runs
#     it on synthetic scans made by the installed converter;
#  3. builds the same main.cpp with pkg-config instead of CMake;
#  4. builds and runs tests/package/consumer (the engine alone, through the
#     umbrella header);
#  5. when levelfuse was built with MPI, builds tests/package/mpi_consumer
#     with the package's component mpi and runs it as one rank.
# Invoked by CTest with -DBUILD_DIR, -DSOURCE_DIR (the repository), -DWORK_DIR and
# -DOPENVDB_MODULE_DIR (where this machine's FindOpenVDB.cmake was found).

function(run)
  cmake_parse_arguments(PARSE_ARGV 0 _run "" "WHAT;WORKING_DIRECTORY" "COMMAND")
  if(NOT _run_WORKING_DIRECTORY)
    set(_run_WORKING_DIRECTORY "${WORK_DIR}")
  endif()
  execute_process(COMMAND ${_run_COMMAND} WORKING_DIRECTORY "${_run_WORKING_DIRECTORY}"
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(rc)
    message(FATAL_ERROR "${_run_WHAT} failed (${rc}):\n${out}")
  endif()
endfunction()

# The fenced block that follows the line "<!-- consumer: NAME -->" in the README.
function(readme_block readme name result)
  string(FIND "${readme}" "<!-- consumer: ${name} -->" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "README.md has no block marked <!-- consumer: ${name} -->")
  endif()
  string(SUBSTRING "${readme}" ${at} -1 rest)
  string(FIND "${rest}" "```" open)
  string(SUBSTRING "${rest}" ${open} -1 rest)
  string(FIND "${rest}" "\n" lineEnd)
  math(EXPR bodyStart "${lineEnd} + 1")
  string(SUBSTRING "${rest}" ${bodyStart} -1 rest)
  string(FIND "${rest}" "\n```" close)
  math(EXPR bodyLength "${close} + 1")
  string(SUBSTRING "${rest}" 0 ${bodyLength} body)
  set(${result} "${body}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE "${WORK_DIR}")
file(MAKE_DIRECTORY "${WORK_DIR}")
set(prefix "${WORK_DIR}/prefix")
run(WHAT "installing" COMMAND "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}")

# 1. Relocatable (no folder of this build, of this source tree or where this
#    machine keeps FindOpenVDB.cmake), complete, no templates.
file(GLOB_RECURSE packageFiles "${prefix}/*.cmake" "${prefix}/*.pc")
foreach(f ${packageFiles})
  file(READ "${f}" text)
  foreach(machinePath "${BUILD_DIR}" "${SOURCE_DIR}" "${OPENVDB_MODULE_DIR}")
    string(FIND "${text}" "${machinePath}" found)
    if(NOT found EQUAL -1)
      message(FATAL_ERROR "${f} names ${machinePath}: the package is not relocatable")
    endif()
  endforeach()
endforeach()
file(GLOB_RECURSE templates "${prefix}/include/*.in")
if(templates)
  message(FATAL_ERROR "templates installed: ${templates}")
endif()
file(READ "${prefix}/include/levelfuse/levelfuse.h" umbrella)
file(GLOB_RECURSE publicHeaders RELATIVE "${prefix}/include" "${prefix}/include/levelfuse/*.h")
foreach(h ${publicHeaders})
  # The MPI layer's headers need mpi.h: a consumer of the component mpi includes them.
  if(h MATCHES "/detail/" OR h MATCHES "^levelfuse/mpi/" OR h STREQUAL "levelfuse/levelfuse.h")
    continue()
  endif()
  string(FIND "${umbrella}" "#include <${h}>" found)
  if(found EQUAL -1)
    message(FATAL_ERROR "levelfuse/levelfuse.h does not include ${h}")
  endif()
endforeach()

# 2. The README's consumer, with CMake.
file(READ "${SOURCE_DIR}/README.md" readme)
readme_block("${readme}" "CMakeLists.txt" consumerCMake)
readme_block("${readme}" "main.cpp" consumerMain)
set(readmeConsumer "${WORK_DIR}/readme-consumer")
file(WRITE "${readmeConsumer}/CMakeLists.txt" "${consumerCMake}")
file(WRITE "${readmeConsumer}/main.cpp" "${consumerMain}")
run(WHAT "configuring the README's consumer"
    COMMAND "${CMAKE_COMMAND}" -S "${readmeConsumer}" -B "${readmeConsumer}/build" "-DCMAKE_PREFIX_PATH=${prefix}"
            -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS=-Wall -Wextra -Werror")
run(WHAT "building the README's consumer" COMMAND "${CMAKE_COMMAND}" --build "${readmeConsumer}/build")
if(EXISTS "${prefix}/bin/levelfuse")
  run(WHAT "making scans with the installed converter"
      COMMAND "${prefix}/bin/levelfuse" synth --shape sphere --resolution 48 -o "${WORK_DIR}/scans")
  run(WHAT "running the README's consumer"
      COMMAND "${readmeConsumer}/build/reconstruct" "${WORK_DIR}/scans/scans.json" "${WORK_DIR}/sphere.vdb")
  execute_process(COMMAND "${prefix}/bin/levelfuse" info "${WORK_DIR}/sphere.vdb" OUTPUT_VARIABLE info RESULT_VARIABLE rc)
  if(rc OR NOT info MATCHES "'surface': float level set" OR NOT info MATCHES "'weight'")
    message(FATAL_ERROR "the README's consumer wrote no level set with its weight grid:\n${info}")
  endif()
else()
  message(STATUS "the converter is not installed (LEVELFUSE_BUILD_TOOLS=OFF): the README's consumer built, not run")
endif()

# 3. The same program with pkg-config.
find_program(PKG_CONFIG pkg-config)
if(PKG_CONFIG)
  file(GLOB_RECURSE pcFile "${prefix}/*/levelfuse.pc")
  get_filename_component(pcDir "${pcFile}" DIRECTORY)
  set(ENV{PKG_CONFIG_PATH} "${pcDir}")
  execute_process(COMMAND "${PKG_CONFIG}" --cflags --libs levelfuse OUTPUT_VARIABLE flags
                  RESULT_VARIABLE rc OUTPUT_STRIP_TRAILING_WHITESPACE)
  if(rc)
    message(FATAL_ERROR "pkg-config does not know levelfuse (${pcFile})")
  endif()
  separate_arguments(flags UNIX_COMMAND "${flags}")
  run(WHAT "building the README's consumer with pkg-config"
      COMMAND c++ -O1 -Wall -Wextra -Werror "${readmeConsumer}/main.cpp" ${flags} -o "${WORK_DIR}/reconstruct-pc")
else()
  message(FATAL_ERROR "pkg-config is not installed (Debian: pkg-config)")
endif()

# 4. The engine alone, through the umbrella header.
run(WHAT "configuring the engine consumer"
    COMMAND "${CMAKE_COMMAND}" -S "${SOURCE_DIR}/tests/package/consumer" -B "${WORK_DIR}/engine"
            "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_BUILD_TYPE=Release)
run(WHAT "building the engine consumer" COMMAND "${CMAKE_COMMAND}" --build "${WORK_DIR}/engine")
run(WHAT "running the engine consumer" COMMAND "${WORK_DIR}/engine/consumer")

# 5. The MPI layer, the package's component mpi, when it was built (run without mpirun: one rank).
file(GLOB mpiLibrary "${prefix}/lib*/liblevelfuse_mpi.a" "${prefix}/lib*/*/liblevelfuse_mpi.a")
if(mpiLibrary)
  run(WHAT "configuring the MPI consumer"
      COMMAND "${CMAKE_COMMAND}" -S "${SOURCE_DIR}/tests/package/mpi_consumer" -B "${WORK_DIR}/mpi"
              "-DCMAKE_PREFIX_PATH=${prefix}" -DCMAKE_BUILD_TYPE=Release)
  run(WHAT "building the MPI consumer" COMMAND "${CMAKE_COMMAND}" --build "${WORK_DIR}/mpi")
  run(WHAT "running the MPI consumer" COMMAND "${WORK_DIR}/mpi/mpi_consumer")
else()
  message(STATUS "levelfuse was built without MPI: no component mpi to test")
endif()
