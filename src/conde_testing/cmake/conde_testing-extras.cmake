# conde_add_pytests(DIRECTORY): registers the pytest files (test_*.py) of DIRECTORY as one catkin
# test of the calling package, so that `catkin_make run_tests`, `run_tests_<package>_pytest`,
# `ctest` and `colcon test` run them; results go to the package's JUnit XML like gtest's.
# pytest runs with /usr/bin/python3 (PYTHON_EXECUTABLE), the Python that has rospy.
function(conde_add_pytests directory)
  get_filename_component(_dir "${directory}" ABSOLUTE)
  get_filename_component(_name "${_dir}" NAME)
  set(_xml "${CATKIN_TEST_RESULTS_DIR}/${PROJECT_NAME}/pytest-${_name}.xml")
  catkin_run_tests_target("pytest" "${_name}" "pytest-${_name}.xml"
    COMMAND "${PYTHON_EXECUTABLE} -m pytest -q -p no:cacheprovider -o python_files=test_*.py ${_dir} --junit-xml=${_xml}"
    WORKING_DIRECTORY "${CMAKE_CURRENT_SOURCE_DIR}")
endfunction()
