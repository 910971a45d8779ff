"""tests/summarize_results.py, the closing summary of the test command: counts, the failed cases,
and why each failed (the end of its traceback), on result files written as rosunit, pytest and
gtest write them."""
import os
import subprocess
import sys

import pytest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "summarize_results.py")

ROSUNIT_FAILED = """<?xml version="1.0" encoding="utf-8"?>
<testsuite errors="0" failures="1" name="unittest.suite.TestSuite" tests="2" time="61.0">
  <testcase classname="__main__.CarTest" name="test_1_radius" time="30.0">
    <failure type="AssertionError"><![CDATA[
  File "/usr/lib/python3.11/unittest/case.py", line 57, in testPartExecutor
    yield
  File "tests/car_checks.py", line 120, in test_1_radius
    self.assertLess(abs(radius_m / wheels_m - 1), GEOMETRY_TOLERANCE)
AssertionError: 0.041 not less than 0.03
]]></failure>
  </testcase>
  <testcase classname="__main__.CarTest" name="test_2_timeout" time="31.0"/>
</testsuite>
"""

PYTEST_ERROR_AND_SKIP = """<?xml version="1.0" encoding="utf-8"?>
<testsuites><testsuite name="pytest" errors="1" failures="0" skipped="1" tests="3">
  <testcase classname="test.test_node" name="test_starts"/>
  <testcase classname="test.test_node" name="test_needs_display"><skipped message="no display"/></testcase>
  <testcase classname="test.test_node" name="test_bad_world">
    <error message="failed on setup with &quot;FileNotFoundError: worlds/x.yaml&quot;"/>
  </testcase>
</testsuite></testsuites>
"""

GTEST_PASSED = """<?xml version="1.0" encoding="UTF-8"?>
<testsuites tests="2" failures="0" errors="0" name="AllTests">
  <testsuite name="Engine" tests="2" failures="0" errors="0">
    <testcase name="Falls" status="run" classname="Engine"/>
    <testcase name="Rolls" status="run" classname="Engine"/>
  </testsuite>
</testsuites>
"""


def summarize(folder):
    run = subprocess.run([sys.executable, SCRIPT, str(folder)], capture_output=True, text=True, timeout=60)
    return run.returncode, run.stdout.splitlines()


@pytest.fixture
def results(tmp_path):
    def write(name, text):
        path = tmp_path / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return tmp_path, write


def test_all_passed_exits_0(results):
    folder, write = results
    write("conde_physics/gtest-engine.xml", GTEST_PASSED)
    code, lines = summarize(folder)
    assert code == 0
    assert lines[-1] == "2 passed, 0 failed, 0 skipped"
    assert not [line for line in lines if line.startswith(("FAILED", "---"))]


def test_a_failure_is_listed_last_with_why_above_it(results):
    folder, write = results
    write("conde_physics/gtest-engine.xml", GTEST_PASSED)
    write("conde_tests/rosunit-car.xml", ROSUNIT_FAILED)
    write("conde_tracking/pytest-test.xml", PYTEST_ERROR_AND_SKIP)
    code, lines = summarize(folder)
    assert code == 1
    assert lines[-1] == "4 passed, 2 failed, 1 skipped"
    assert lines[-3:-1] == ["FAILED conde_tests/rosunit-car.xml: __main__.CarTest.test_1_radius",
                            "FAILED conde_tracking/pytest-test.xml: test.test_node.test_bad_world"]
    text = "\n".join(lines)
    # The end of the rosunit traceback (the assertion and its values), under the case's name.
    why = text.index("--- conde_tests/rosunit-car.xml: __main__.CarTest.test_1_radius")
    assert text.index("AssertionError: 0.041 not less than 0.03", why) < text.index("Test result files")
    assert "self.assertLess(abs(radius_m / wheels_m - 1), GEOMETRY_TOLERANCE)" in text
    # An error without text: its message attribute.
    assert 'failed on setup with "FileNotFoundError: worlds/x.yaml"' in text


def test_only_the_end_of_a_long_traceback(results):
    folder, write = results
    frames = "".join(f'  File "deep.py", line {i}, in level_{i}\n' for i in range(40))
    write("t/rosunit-deep.xml", ROSUNIT_FAILED.replace("  File \"/usr/lib", frames + "  File \"/usr/lib"))
    _, lines = summarize(folder)
    assert "level_0" not in "\n".join(lines)
    assert any("AssertionError: 0.041 not less than 0.03" in line for line in lines)


def test_an_unreadable_file_fails(results):
    folder, write = results
    write("conde_sim/rosunit-cut.xml", "<testsuite><testcase name='x'>")
    code, lines = summarize(folder)
    assert code == 1
    assert lines[-2].startswith("FAILED ") and "rosunit-cut.xml: unreadable result file" in lines[-2]
    assert lines[-1] == "0 passed, 1 failed, 0 skipped"


def test_no_result_at_all_fails(tmp_path):
    code, lines = summarize(tmp_path)
    assert code == 1
    assert lines[-1] == "0 passed, 0 failed, 0 skipped"
