# The Python module as `cmake --install` puts it under a prefix: importable
# from the directory the build says, and working.
file(REMOVE_RECURSE "${WORK_DIR}")
execute_process(COMMAND ${CMAKE_COMMAND} --install "${BUILD_DIR}" --prefix "${WORK_DIR}"
                RESULT_VARIABLE installed OUTPUT_QUIET)
if(NOT installed EQUAL 0)
  message(FATAL_ERROR "cmake --install failed")
endif()
execute_process(
  COMMAND ${CMAKE_COMMAND} -E env "PYTHONPATH=${WORK_DIR}/${MODULE_DIR}" "${PYTHON}" -c
          "import levelfuse, pathlib; assert pathlib.Path(levelfuse.__file__).is_relative_to('${WORK_DIR}'), levelfuse.__file__; print(levelfuse.__file__, levelfuse.__version__)"
  RESULT_VARIABLE imported)
if(NOT imported EQUAL 0)
  message(FATAL_ERROR "the installed module cannot be imported from ${WORK_DIR}/${MODULE_DIR}")
endif()
