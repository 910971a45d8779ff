"""What every rospy node of the project does alike (conde_common.node_support), checked on the
real nodes against a real roscore:

- an unknown private parameter stops the node at start-up with "<node>: error: unknown parameter
  /<ros name>/<param> (known: ...)" and exit status 1 (before, a typo was silently ignored);
- SIGTERM while the node starts up (waiting for its inputs) ends it promptly with status 0.

Every node runs with a pseudo-terminal on stdin, as from a shell (the teleops read keys)."""
import os
import pty
import signal
import subprocess
import time

import pytest
import rosgraph

# (package, executable, ROS node name, name in its error lines)
NODES = [
    ("conde_tracking", "conde_tracking", "/conde_tracking", "conde_tracking"),
    ("conde_semaphore", "conde_semaphore", "/conde_semaphore", "conde_semaphore"),
    ("conde_decision", "conde_decision", "/conde_decision", "conde_decision"),
    ("conde_control", "conde_control", "/conde_control", "conde_control"),
    ("conde_signalling_panel_control", "signalling_panel_controller", "/signalling_panel_controller",
     "signalling_panel_controller"),
    ("conde_teleop", "conde_teleop", "/conde_teleop", "conde_teleop"),
    ("conde_racing", "lap_timer", "/lap_timer", "lap_timer"),
    ("conde_racing", "gap_follower", "/gap_follower", "gap_follower"),
    ("conde_racing", "ackermann_teleop", "/ackermann_teleop", "ackermann_teleop"),
    ("conde_major", "major_ackermann_controller", "/ackermann_controller", "major_ackermann_controller"),
    ("conde_eval", "odometry_test_node", "/odometry_test", "odometry_test"),
    ("conde_eval", "start_when_ready", "/start_when_ready", "start_when_ready"),
    ("conde_referee", "conde_referee", "/conde_referee", "conde_referee"),
    ("conde_humanoid", "nao_pose", "/nao_pose", "nao_pose"),
]
IDS = [node[1] for node in NODES]


def start(env, package, executable, *args):
    """The node under rosrun with a pseudo-terminal on stdin; (process, terminal fd to close)."""
    parent, child = pty.openpty()
    process = subprocess.Popen(["rosrun", package, executable, *args], env=env, stdin=child,
                               stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True)
    os.close(child)
    return process, parent


@pytest.mark.parametrize("package, executable, ros_name, name", NODES, ids=IDS)
def test_unknown_private_parameter_stops_the_node(master, package, executable, ros_name, name):
    process, terminal = start(master, package, executable, "_no_such_param:=1")
    try:
        _, stderr = process.communicate(timeout=60)
    finally:
        os.close(terminal)
    errors = [line for line in stderr.splitlines() if line.startswith(name + ": error: ")]
    assert process.returncode == 1, stderr
    assert errors and errors[0].startswith(
        f"{name}: error: unknown parameter {ros_name}/no_such_param (known: "), stderr
    rosgraph.Master("/node_conventions_test", master_uri=master["ROS_MASTER_URI"]).deleteParam(ros_name)


# The nodes that wait for inputs at start-up without a simulator (the others need a terminal's
# keys, a config file or a simulator to get that far, or exit by themselves).
WAITING = ("conde_tracking", "conde_semaphore", "conde_decision", "conde_control", "gap_follower", "start_when_ready")
WAITING_NODES = [n for n in NODES if n[1] in WAITING]


@pytest.mark.parametrize("package, executable, ros_name, name", WAITING_NODES, ids=[n[1] for n in WAITING_NODES])
def test_sigterm_during_start_up_ends_the_node(master, package, executable, ros_name, name):
    master_api = rosgraph.Master("/node_conventions_test", master_uri=master["ROS_MASTER_URI"])
    process, terminal = start(master, package, executable)
    try:
        deadline = time.monotonic() + 60
        while True:  # registered with the master: rospy is initialised, start-up under way
            try:
                master_api.lookupNode(ros_name)
                break
            except rosgraph.MasterError:
                assert process.poll() is None, process.communicate()[1]
                assert time.monotonic() < deadline, f"{ros_name} did not register"
                time.sleep(0.05)
        time.sleep(0.5)  # into its start-up waits
        os.killpg(process.pid, signal.SIGTERM)
        try:
            _, stderr = process.communicate(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(process.pid, signal.SIGKILL)
            pytest.fail(f"{name} still ran 30 s after SIGTERM")
        assert process.returncode == 0, stderr
    finally:
        os.close(terminal)


def test_the_driving_stack_runs_under_a_namespace(master, tmp_path):
    """The four nodes of the driving stack started in namespace /robot1 (several robots or runs on
    one master): every topic they publish and subscribe moves under /robot1."""
    master_api = rosgraph.Master("/node_conventions_test", master_uri=master["ROS_MASTER_URI"])
    env = dict(master, ROS_NAMESPACE="/robot1")
    stack = [("conde_tracking", "conde_tracking"), ("conde_semaphore", "conde_semaphore"),
             ("conde_decision", "conde_decision"), ("conde_control", "conde_control")]
    processes = [subprocess.Popen(["rosrun", package, executable], env=env, stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL, start_new_session=True) for package, executable in stack]
    expected = {
        "publishes": {"/robot1/conde_signal", "/robot1/conde_control_reference", "/robot1/conde_decision/state",
                      "/robot1/conde_decision/marker", "/robot1/cmd_vel"},
        # (conde_tracking waits for its left camera's CameraInfo before it subscribes to the rest)
        "subscribes": {"/robot1/conde_camera_tracking_left/camera_info_left",
                       "/robot1/conde_camera_signalling_panel/image_raw", "/robot1/conde_lane", "/robot1/conde_signal",
                       "/robot1/odom", "/robot1/conde_control_reference"},
    }
    try:
        deadline = time.monotonic() + 60
        while True:
            publishers, subscribers, _ = master_api.getSystemState()
            published = {topic for topic, nodes in publishers if any(n.startswith("/robot1/") for n in nodes)}
            subscribed = {topic for topic, nodes in subscribers if any(n.startswith("/robot1/") for n in nodes)}
            if expected["publishes"] <= published and expected["subscribes"] <= subscribed:
                break
            assert time.monotonic() < deadline, (f"missing publications {expected['publishes'] - published}, "
                                                 f"subscriptions {expected['subscribes'] - subscribed}")
            time.sleep(0.2)
        # TF and the clock are shared by every robot (frames carry prefixes); rosout is ROS's own.
        shared = {"/tf", "/tf_static", "/clock", "/rosout"}
        ours = (published | subscribed) - shared
        assert all(t.startswith("/robot1/") for t in ours), sorted(t for t in ours if not t.startswith("/robot1/"))
    finally:
        for process in processes:
            os.killpg(process.pid, signal.SIGTERM)
        for process in processes:
            process.wait(timeout=30)
