"""The simulator's services from the command line, as a user calls them (rosservice), against the
real node: set_start_pose looks its robot up in the step loop's thread and answers for it."""
import subprocess
import time

import pytest
import rosgraph

from test_bad_input import FLAT_WORLD, GOOD_URDF


def service_uri(master_api):
    """The server of /conde_sim/set_start_pose the master knows, None when none is registered."""
    try:
        return master_api.lookupService("/conde_sim/set_start_pose")
    except rosgraph.MasterError:
        return None


@pytest.fixture
def paused_sim(master):
    master_api = rosgraph.Master("/sim_services_test", master_uri=master["ROS_MASTER_URI"])
    master_api.setParam("/robot_description", GOOD_URDF)
    stale_uri = service_uri(master_api)
    node = subprocess.Popen(["rosrun", "conde_sim", "conde_sim_node", f"_world_file:={FLAT_WORLD}", "_paused:=true",
                             "_real_time_factor:=0"], env=master, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True)
    deadline = time.monotonic() + 60
    # Wait for this node's service: the master may still list the one of an earlier test's node
    # (seen on a loaded machine), and a call would then go to a server that is gone.
    while service_uri(master_api) in (None, stale_uri):
        assert node.poll() is None, node.communicate()[0]
        assert time.monotonic() < deadline, "no /conde_sim/set_start_pose"
        time.sleep(0.1)
    yield master
    node.terminate()
    node.wait(timeout=60)  # a process on a slow, busy machine


def call(env, request):
    out = subprocess.run(["rosservice", "call", "/conde_sim/set_start_pose", request], env=env, capture_output=True,
                         text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    return out.stdout


def test_set_start_pose_of_an_unknown_robot_is_refused(paused_sim):
    out = call(paused_sim, "{robot: 'nope', x_m: 1.0, y_m: 0.0, yaw_rad: 0.0}")
    assert "success: False" in out and "message: \"no robot named 'nope'\"" in out, out


def test_set_start_pose_of_the_robot(paused_sim):
    out = call(paused_sim, "{robot: '', x_m: 1.0, y_m: 2.0, yaw_rad: 0.5}")
    assert "success: True" in out and "message: \"robot 'box_bot' reset to the new start pose\"" in out, out


def test_set_start_pose_rejects_non_finite_numbers(paused_sim):
    out = call(paused_sim, "{robot: '', x_m: .nan, y_m: 0.0, yaw_rad: 0.0}")
    assert "success: False" in out and "x_m, y_m and yaw_rad must be finite" in out, out
