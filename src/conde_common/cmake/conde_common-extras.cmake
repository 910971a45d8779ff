# conde_python_package([SHARE_DIRS dir...]): what each Python package of conde_sim declares after
# catkin_install_python: its SHARE_DIRS (config, launch, ...) installed to the package's share
# folder and, when testing is on, its test/test_*.py registered as one catkin test through
# conde_testing's conde_add_pytests (catkin_make run_tests, ctest and colcon test run them).
macro(conde_python_package)
  cmake_parse_arguments(_conde_python "" "" "SHARE_DIRS" ${ARGN})
  if(_conde_python_UNPARSED_ARGUMENTS)
    message(FATAL_ERROR "conde_python_package: unknown arguments: ${_conde_python_UNPARSED_ARGUMENTS}")
  endif()
  if(_conde_python_SHARE_DIRS)
    install(DIRECTORY ${_conde_python_SHARE_DIRS} DESTINATION ${CATKIN_PACKAGE_SHARE_DESTINATION})
  endif()
  if(CATKIN_ENABLE_TESTING)
    find_package(conde_testing REQUIRED)
    conde_add_pytests(test)
  endif()
endmacro()
