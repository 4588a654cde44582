# The Python module (src/python): pybind11 and the interpreter it builds for,
# numpy at run time, and Boost.Python, through which a grid crosses to
# pyopenvdb (python3-openvdb, OpenVDB's own binding) without a copy.
# Sets LEVELFUSE_HAVE_PYTHON.

if(NOT DEFINED Python3_EXECUTABLE AND EXISTS /usr/bin/python3)
  # Debian's interpreter, whose packages (numpy, pytest, pyopenvdb) the module is used with.
  set(Python3_EXECUTABLE /usr/bin/python3)
endif()
find_package(Python3 COMPONENTS Interpreter Development.Module OPTIONAL_COMPONENTS Development.Embed)
find_package(pybind11 CONFIG QUIET)
set(LEVELFUSE_HAVE_PYTHON OFF)
if(Python3_FOUND AND pybind11_FOUND)
  set(_lf_boost_python python${Python3_VERSION_MAJOR}${Python3_VERSION_MINOR})
  find_package(Boost QUIET COMPONENTS ${_lf_boost_python})
  if(TARGET Boost::${_lf_boost_python})
    set(LEVELFUSE_HAVE_PYTHON ON)
    set(LEVELFUSE_BOOST_PYTHON Boost::${_lf_boost_python})
    set(LEVELFUSE_PYTHON_INSTALL_DIR
        "lib/python${Python3_VERSION_MAJOR}.${Python3_VERSION_MINOR}/dist-packages"
        CACHE STRING "Where cmake --install puts the Python module, under the prefix")
    message(STATUS "levelfuse: the Python module for ${Python3_EXECUTABLE} (${Python3_VERSION})")
  endif()
endif()
if(NOT LEVELFUSE_HAVE_PYTHON)
  message(STATUS "levelfuse: no Python module (install pybind11-dev python3-dev libboost-python-dev)")
endif()
