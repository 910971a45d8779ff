"""Makes the shared test plumbing (src/conde_testing) importable without building the workspace,
and holds the fixtures that several test files use."""

import os
import sys

import pytest

TESTING_SRC_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                               "src", "conde_testing", "src")
if TESTING_SRC_DIR not in sys.path:
    sys.path.insert(0, TESTING_SRC_DIR)

#: The container tests (image builds, the main job and the unit tier inside the images, noVNC).
CONTAINER_TEST_FILES = ["test_container_images.py", "test_novnc_rviz.py"]
# tests/run_all_tests.sh runs them in a pytest of their own beside the others (most of their time
# is podman building and running images at a low CPU priority) and sets CONDE_CONTAINER_TESTS=apart
# for the catkin run of this folder, which then leaves them out.
collect_ignore = CONTAINER_TEST_FILES if os.environ.get("CONDE_CONTAINER_TESTS") == "apart" else []


@pytest.fixture(scope="module")
def master():
    """A roscore on a free loopback port; yields the environment the nodes run in against it."""
    from conde_testing.ros_harness import Roscore

    with Roscore("conde_sim") as core:
        yield core.env


@pytest.fixture(scope="module")
def conde_master(master):
    """`master` with Conde's URDF (xacro of conde_description) in /robot_description."""
    import subprocess

    import rosgraph

    description = subprocess.run(["rospack", "find", "conde_description"], env=master, capture_output=True, text=True,
                                 check=True).stdout.strip()
    urdf = subprocess.run(["xacro", description + "/robots/conde.urdf.xacro"], env=master, capture_output=True,
                          text=True, check=True).stdout
    rosgraph.Master("/conde_master_fixture", master_uri=master["ROS_MASTER_URI"]).setParam("/robot_description", urdf)
    return master


def run_checks(script, engine, out_dir, env, timeout_s):
    """Runs a checks script of this folder (`script ENGINE OUTPUT_DIR`, ROS master in `env`) and
    returns the JSON objects it printed, one a line; fails with its output when it fails."""
    import json
    import subprocess

    out = subprocess.run(["/usr/bin/python3", os.path.join(os.path.dirname(os.path.abspath(__file__)), script), engine,
                          str(out_dir)], env=env, capture_output=True, text=True, timeout=timeout_s)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-3000:]
    return [json.loads(line) for line in out.stdout.splitlines() if line.startswith("{")]
