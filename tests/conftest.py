"""Makes the shared test plumbing (src/conde_testing) importable without building the workspace,
and holds the fixtures that several test files use."""

import os
import sys

import pytest

TESTING_SRC_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                               "src", "conde_testing", "src")
if TESTING_SRC_DIR not in sys.path:
    sys.path.insert(0, TESTING_SRC_DIR)


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
