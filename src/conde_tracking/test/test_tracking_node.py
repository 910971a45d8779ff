"""The conde_tracking node in a real ROS graph: the simulator (conde_bringup sim.launch, paused,
real_time_factor 0) with its own roscore on a free loopback port, the node started with rosrun,
and this test process as a ROS node that steps the simulation, plays test cameras (real images
rendered by the simulator, test/data) and listens to /conde_lane.

One simulator serves the whole module: rospy joins one master per process.  Nothing waits on a
fixed sleep: every wait polls a condition (a log line, a subscription in the master, a message)
until a generous wall-clock deadline, stepping the simulation where the condition needs it.

Needs the built workspace sourced (source devel/setup.bash):
    /usr/bin/python3 -m pytest -q -o python_files="test_*.py" src/conde_tracking/test/test_tracking_node.py
"""
import math
import os
import re
import signal
import subprocess
import threading
import time

import numpy as np
import pytest
import rosgraph
import rospy
import tf2_ros
from conde_msgs.msg import DecisionState, LaneMeasurement
from conde_msgs.srv import SetStartPose, StepSimulation
from geometry_msgs.msg import TransformStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import CameraInfo, Image

from conde_testing.ros_harness import free_port, joined_as_node
from conde_tracking.bay_truth import lines_in_robot_frame
from conde_worlds.track_geometry import LANE_OFFSET, X_REF, build_track

DATA = os.path.join(os.path.dirname(os.path.abspath(__file__)), "data")
STARTUP_TIMEOUT_S = 120.0  # wall clock, for anything that starts a process on a busy 2-core machine
CONDITION_TIMEOUT_S = 120.0
POLL_S = 0.05  # wall-clock interval between two looks at a condition
CAMERA_PERIOD_STEPS = 34  # the ground cameras render at 30 Hz of simulated time; 1 ms physics steps
TIMING_LINE = re.compile(
    r"conde_tracking: timing: (\d+) frames, mean (\d+\.\d\d) ms, max (\d+\.\d\d) ms CPU per frame$")

SIM_IMAGE_TOPICS = ("/conde_camera_tracking_left/image_raw", "/conde_camera_tracking_right/image_raw")


def wrap(angle_rad):
    return (angle_rad + math.pi) % (2 * math.pi) - math.pi


def wait_until(condition, what, timeout_s=CONDITION_TIMEOUT_S, between=None):
    """Polls condition() until it returns something true, which it returns; between() runs after each
    miss (e.g. steps the simulation).  what() describes the condition when it times out."""
    deadline = time.monotonic() + timeout_s
    while True:
        result = condition()
        if result:
            return result
        if time.monotonic() > deadline:
            raise AssertionError(f"not within {timeout_s:.0f} s: {what()}")
        if between is not None:
            between()
        time.sleep(POLL_S)


class Process:
    """A child process (own process group) whose stdout + stderr lines are collected."""

    def __init__(self, args, env, name=""):
        self.args, self.name = args, name
        self.proc = subprocess.Popen(args, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                     start_new_session=True)
        self.lines = []
        self.interrupt_after = None  # SIGINT as soon as a line ends with this text
        self._reader = threading.Thread(target=self._read, daemon=True)
        self._reader.start()

    def _read(self):
        for line in self.proc.stdout:
            self.lines.append(line.rstrip("\n"))
            if self.interrupt_after and self.lines[-1].endswith(self.interrupt_after) and self.running():
                self.proc.send_signal(signal.SIGINT)

    def output(self):
        return "\n".join(self.lines)

    def running(self):
        return self.proc.poll() is None

    def lines_ending_with(self, text):
        return [line for line in list(self.lines) if line.endswith(text)]

    def matches(self, pattern):
        return [m for m in (pattern.search(line) for line in list(self.lines)) if m]

    def stop(self, timeout_s=60.0):
        """SIGINT (what roslaunch sends), then SIGKILL to the group.  True if SIGINT sufficed."""
        if self.running():
            self.proc.send_signal(signal.SIGINT)
        try:
            self.proc.wait(timeout=timeout_s)
            clean = True
        except subprocess.TimeoutExpired:
            os.killpg(self.proc.pid, signal.SIGKILL)
            self.proc.wait(timeout=30)
            clean = False
        self._reader.join(timeout=10)
        return clean


class Simulation:
    """The paused simulator and this process's connection to its master."""

    def __init__(self, env, master_uri):
        self.env, self.master = env, rosgraph.Master("/test_tracking_node", master_uri=master_uri)
        self._step = rospy.ServiceProxy("/conde_sim/step", StepSimulation)
        self._set_start_pose = rospy.ServiceProxy("/conde_sim/set_start_pose", SetStartPose)
        self._nodes_started = 0

    def step(self, steps):
        resp = self._step(steps)
        assert resp.success, f"/conde_sim/step: {resp.message}"
        return resp.sim_time_s

    def set_start_pose(self, x_m, y_m, yaw_rad):
        resp = self._set_start_pose("", x_m, y_m, yaw_rad)
        assert resp.success, f"/conde_sim/set_start_pose: {resp.message}"

    def subscribes(self, node, topic):
        _, subscribers, _ = self.master.getSystemState()
        return any(t == topic and node in nodes for t, nodes in subscribers)

    def start_node(self, **params):
        """rosrun conde_tracking with the private parameters given.  Each node gets a name of its own:
        rosrun leaves private parameters on the parameter server, where the next node of the same
        name would find them."""
        self._nodes_started += 1
        name = f"conde_tracking_{self._nodes_started}"
        args = (["rosrun", "conde_tracking", "conde_tracking", f"__name:={name}"]
                + [f"_{k}:={v}" for k, v in params.items()])
        return Process(args, self.env, name="/" + name)


@pytest.fixture(scope="module")
def sim():
    if rospy.core.is_initialized():
        pytest.fail("rospy is already initialised in this process (another module joined a master); "
                    "run this module in its own pytest process")
    port = free_port()
    master_uri = f"http://127.0.0.1:{port}"
    env = dict(os.environ, PATH="/usr/bin:" + os.environ.get("PATH", ""), ROS_MASTER_URI=master_uri,
               ROS_IP="127.0.0.1", PYTHONUNBUFFERED="1")
    env.pop("ROS_HOSTNAME", None)
    launch = Process(["roslaunch", "-p", str(port), "conde_bringup", "sim.launch", "paused:=true",
                      "real_time_factor:=0", "clock_rate:=100"], env)
    try:
        master = rosgraph.Master("/test_tracking_node", master_uri=master_uri)

        def master_up():
            assert launch.running(), f"roslaunch sim.launch exited:\n{launch.output()}"
            return master.is_online()

        wait_until(master_up, lambda: f"the master of sim.launch on port {port}\n{launch.output()}", STARTUP_TIMEOUT_S)
        with joined_as_node(master_uri, "test_tracking_node"):
            for service in ("/conde_sim/step", "/conde_sim/set_start_pose"):
                try:
                    rospy.wait_for_service(service, timeout=STARTUP_TIMEOUT_S)
                except rospy.ROSException:
                    pytest.fail(f"no service {service} within {STARTUP_TIMEOUT_S:.0f} s:\n{launch.output()}")
            yield Simulation(env, master_uri)
    finally:
        launch.stop()


@pytest.fixture
def node_processes():
    """Nodes a test starts; each is stopped when the test ends and must stop on SIGINT."""
    started = []
    yield started
    hung = [proc for proc in started if not proc.stop()]
    assert not hung, "did not stop on SIGINT within 60 s: " + ", ".join(proc.name for proc in hung)


def wait_until_node_ready(sim, node, image_topics, step=True):
    """Until the node subscribes to both image topics (its start-up is done), stepping the
    simulation meanwhile if asked (the cameras' CameraInfo only flows while it steps)."""
    def ready():
        assert node.running(), f"conde_tracking exited during start-up:\n{node.output()}"
        return all(sim.subscribes(node.name, t) for t in image_topics)

    wait_until(ready, lambda: f"{node.name} subscribed to {', '.join(image_topics)}\n{node.output()}",
               STARTUP_TIMEOUT_S, between=(lambda: sim.step(50)) if step else None)


def wait_for_log_line(node, text, between=None):
    def logged():
        assert node.running(), f"conde_tracking exited:\n{node.output()}"
        return node.lines_ending_with(text)

    return wait_until(logged, lambda: f"a line ending with {text!r} from conde_tracking\n--- output:\n{node.output()}",
                      STARTUP_TIMEOUT_S, between)


class LaneListener:
    """Collects /conde_lane."""

    def __init__(self):
        self.messages, self.lock = [], threading.Lock()
        self.sub = rospy.Subscriber("/conde_lane", LaneMeasurement, self._on_lane, queue_size=100)

    def _on_lane(self, msg):
        with self.lock:
            self.messages.append(msg)

    def since(self, stamp_s):
        with self.lock:
            return [m for m in self.messages if m.header.stamp.to_sec() >= stamp_s]

    def before(self, stamp_s):
        with self.lock:
            return [m for m in self.messages if m.header.stamp.to_sec() < stamp_s]

    def close(self):
        self.sub.unregister()


# --- a: a camera topic that never publishes ------------------------------------------------------

def test_names_the_camera_info_topic_it_waits_for_and_stops_on_sigint_right_after(sim, node_processes):
    """The left CameraInfo comes from the stepped simulator; the right one's topic has no publisher.
    SIGINT comes the moment the line is read, while the node still reports it to /rosout (a call to
    the master): the node must exit all the same, with status 0."""
    missing = "/test_missing/camera_info"
    line = f"conde_tracking: waiting for CameraInfo on {missing}"
    node = sim.start_node(camera_right_info=missing)
    node.interrupt_after = line
    node_processes.append(node)
    wait_until(lambda: not node.running(), lambda: f"{node.name} logged {line!r} and exited on SIGINT\n{node.output()}",
               STARTUP_TIMEOUT_S, between=lambda: sim.step(50))
    assert node.lines_ending_with(line), node.output()
    assert node.proc.returncode == 0, node.output()


@pytest.mark.parametrize("name, value, message", [
    ("timing_report_period_s", "0.0", "conde_tracking: parameter ~timing_report_period_s must be > 0 [s], got 0.0"),
    ("white_threshold", "bright", "conde_tracking: parameter ~white_threshold must be of type int, got 'bright'"),
    ("parking_search", "sometimes", "conde_tracking: parameter ~parking_search must be one of auto, always, never, "
                                    "got 'sometimes'"),
])
def test_exits_with_status_1_on_a_bad_parameter(sim, node_processes, name, value, message):
    node = sim.start_node(**{name: value})
    node_processes.append(node)
    wait_until(lambda: not node.running(), lambda: f"{node.name} exited\n{node.output()}", STARTUP_TIMEOUT_S)
    assert node.proc.returncode == 1, node.output()
    assert node.lines_ending_with(message), node.output()


def test_names_the_image_topic_it_waits_for(sim, node_processes):
    """Both CameraInfo come from the stepped simulator, the right images' topic has no publisher."""
    missing = "/test_missing/image_raw"
    node = sim.start_node(camera_right=missing)
    node_processes.append(node)
    wait_until_node_ready(sim, node, (SIM_IMAGE_TOPICS[0], missing))
    wait_for_log_line(node, f"conde_tracking: waiting for images on {missing}",
                      between=lambda: sim.step(CAMERA_PERIOD_STEPS))


# --- b: images of an unexpected size or encoding -------------------------------------------------

def quaternion_xyzw(R):
    """Unit quaternion (x, y, z, w) of a rotation matrix (branch on the largest diagonal term)."""
    t = np.trace(R)
    if t > 0:
        s = 2.0 * math.sqrt(1.0 + t)
        q = ((R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s, 0.25 * s)
    else:
        i = int(np.argmax(np.diag(R)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + R[i, i] - R[j, j] - R[k, k])
        v = [0.0, 0.0, 0.0]
        v[i], v[j], v[k] = 0.25 * s, (R[j, i] + R[i, j]) / s, (R[k, i] + R[i, k]) / s
        q = (*v, (R[k, j] - R[j, k]) / s)
    return q


def image_msg(array, encoding, frame_id):
    msg = Image()
    msg.header.frame_id = frame_id
    msg.height, msg.width = array.shape[:2]
    msg.encoding = encoding
    msg.step = array.strides[0]
    msg.data = array.tobytes()
    return msg


class PlayedCameras:
    """Plays the two ground cameras of one rendered pose (test/data/<pose>.npz) on test topics, from
    this process at about 10 Hz of wall time: CameraInfo, images stamped with a frame counter, and
    the optical frames in TF.  The right image is replaced by `bad_right` until use_good_images()."""

    PREFIX = "/test_cameras"

    def __init__(self, pose, bad_right):
        self.data = np.load(os.path.join(DATA, pose + ".npz"))
        self.topics = {side: (f"{self.PREFIX}/{side}/image_raw", f"{self.PREFIX}/{side}/camera_info")
                       for side in ("left", "right")}
        frames = {side: f"test_cameras_{side}_optical" for side in ("left", "right")}
        transforms = []
        for side, frame in frames.items():
            T = self.data[f"{side}_T_base_optical"]
            t = TransformStamped()
            t.header.frame_id, t.child_frame_id = "base_footprint", frame
            t.transform.translation.x, t.transform.translation.y, t.transform.translation.z = T[:3, 3]
            (t.transform.rotation.x, t.transform.rotation.y, t.transform.rotation.z,
             t.transform.rotation.w) = quaternion_xyzw(T[:3, :3])
            transforms.append(t)
        self._tf = tf2_ros.StaticTransformBroadcaster()
        self._tf.sendTransform(transforms)
        self.infos, self.good = {}, {}
        for side, frame in frames.items():
            image = np.ascontiguousarray(self.data[f"{side}_image"])
            info = CameraInfo()
            info.header.frame_id = frame
            info.height, info.width = image.shape[:2]
            info.distortion_model = "plumb_bob"
            info.D = [float(v) for v in self.data[f"{side}_D"]]
            info.K = [float(v) for v in self.data[f"{side}_K"].ravel()]
            self.infos[side] = info
            self.good[side] = image_msg(image, "rgb8", frame)
        self.bad_right = bad_right
        bad_right.header.frame_id = frames["right"]
        self.first_good_stamp_s = None
        self._pubs = {side: (rospy.Publisher(image, Image, queue_size=1),
                             rospy.Publisher(info, CameraInfo, queue_size=1))
                      for side, (image, info) in self.topics.items()}
        self._frame = 0
        self._use_good = threading.Event()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._play, daemon=True)
        self._thread.start()

    def use_good_images(self):
        self._use_good.set()

    def _play(self):
        while not self._stop.wait(0.1):  # the publishing rate, not a wait for a condition
            self._frame += 1
            stamp = rospy.Time(1000 + self._frame)  # fake capture times: 1 s per frame
            good = self._use_good.is_set()
            if good and self.first_good_stamp_s is None:
                self.first_good_stamp_s = stamp.to_sec()
            for side, (image_pub, info_pub) in self._pubs.items():
                image = self.good[side] if good or side == "left" else self.bad_right
                image.header.stamp = self.infos[side].header.stamp = stamp
                info_pub.publish(self.infos[side])
                image_pub.publish(image)

    def close(self):
        self._stop.set()
        self._thread.join(timeout=10)
        for image_pub, info_pub in self._pubs.values():
            image_pub.unregister()
            info_pub.unregister()


def bad_images():
    right = np.load(os.path.join(DATA, "left_5cm.npz"))["right_image"]
    small = np.ascontiguousarray(right[::2, ::2])  # 80x60
    mono16 = np.ascontiguousarray((right.mean(axis=2) * 256).astype(np.uint16))  # 160x120
    return {"80x60 rgb8": image_msg(small, "rgb8", ""), "160x120 mono16": image_msg(mono16, "mono16", "")}


@pytest.mark.parametrize("bad", ["80x60 rgb8", "160x120 mono16"])
def test_drops_images_of_unexpected_size_or_encoding_and_measures_later_good_ones(sim, node_processes, bad):
    cameras = PlayedCameras("left_5cm", bad_images()[bad])
    lanes = LaneListener()
    try:
        topics = cameras.topics
        node = sim.start_node(camera_left=topics["left"][0], camera_left_info=topics["left"][1],
                              camera_right=topics["right"][0], camera_right_info=topics["right"][1],
                              timing_report_period_s=1.0)
        node_processes.append(node)
        wait_until_node_ready(sim, node, (topics["left"][0], topics["right"][0]), step=False)
        wait_for_log_line(node, f"conde_tracking: {topics['right'][0]}: image {bad} does not match CameraInfo "
                                "160x120 (expected encoding one of: rgb8, bgr8, mono8); dropped")

        cameras.use_good_images()
        measured = wait_until(
            lambda: cameras.first_good_stamp_s is not None and lanes.since(cameras.first_good_stamp_s),
            lambda: f"/conde_lane after good images\n--- node output:\n{node.output()}")
        assert node.running()
        assert not lanes.before(cameras.first_good_stamp_s), "a measurement of an image pair with a bad image"
        truth = cameras.data
        for lane in measured:
            assert lane.confidence == 1.0
            assert lane.header.frame_id == "base_footprint"
            assert abs(lane.lateral_offset_m - float(truth["lateral_offset_m"])) < 0.02
            assert abs(wrap(lane.heading_error_rad - float(truth["heading_error_rad"]))) < math.radians(3.0)
        # the periodic timing line (every 1 s here) counts the measured pairs
        wait_until(lambda: any(int(m.group(1)) > 0 for m in node.matches(TIMING_LINE)),
                   lambda: f"a periodic timing line with frames > 0\n--- node output:\n{node.output()}")
    finally:
        lanes.close()
        cameras.close()


def test_publishes_the_bay_lines_it_sees_while_the_decision_searches(sim, node_processes):
    """Cameras played from a view rendered in the B2 world (south border and divider ahead, the box
    in the north bay): no bay lines while the decision does not look for a parking place (the
    search is off: ~parking_search auto); once conde_decision/state says it does, /conde_lane
    carries both lines at their distance ahead (parking_area.py)."""
    cameras = PlayedCameras("b2v1_bays_ahead_0_5m", Image())
    cameras.use_good_images()
    lanes = LaneListener()
    state_pub = rospy.Publisher("/conde_decision/state", DecisionState, queue_size=1, latch=True)
    try:
        topics = cameras.topics
        node = sim.start_node(camera_left=topics["left"][0], camera_left_info=topics["left"][1],
                              camera_right=topics["right"][0], camera_right_info=topics["right"][1])
        node_processes.append(node)
        wait_until_node_ready(sim, node, (topics["left"][0], topics["right"][0]), step=False)
        off = wait_until(lambda: lanes.since(0.0),
                         lambda: f"/conde_lane with the bays in view\n--- node output:\n{node.output()}")
        assert all(len(lane.bay_line_distances_m) == 0 for lane in off)
        state_pub.publish(DecisionState(state="go_to_parking", parking_search=True))
        wait_until(lambda: node.lines_ending_with("parking-area search on (decision state go_to_parking)"),
                   lambda: f"the search turned on\n--- node output:\n{node.output()}")
        # The first lane after the log line may come from images measured while the state arrived
        # (another thread of the node): the lanes after it are measured with the search on.
        count = len(lanes.since(0.0))
        measured = wait_until(lambda: lanes.since(0.0)[count + 1:],
                              lambda: f"/conde_lane with the search on\n--- node output:\n{node.output()}")
        truth = lines_in_robot_frame(cameras.data["pose_xy_yaw"])
        for lane in measured:
            assert len(lane.bay_line_distances_m) == 2, lane.bay_line_distances_m
            assert abs(lane.bay_line_distances_m[0] - truth["south_border"]) < 0.04
            assert abs(lane.bay_line_distances_m[1] - truth["divider"]) < 0.04
    finally:
        state_pub.unregister()
        lanes.close()
        cameras.close()


# --- c: a real measurement in the simulator, and the timing line at shutdown ----------------------

LANE_X_M = X_REF + LANE_OFFSET  # centre of the east (northbound) lane on the central straight
POSES = {  # name: (lateral offset [m], + = robot left of the lane centre; heading error [rad], + = left)
    "lane centre": (0.0, 0.0),
    "5 cm left": (0.05, 0.0),
    "10 deg left": (0.0, math.radians(10.0)),
}


def test_measures_offset_and_heading_in_the_simulation_and_reports_timing_at_shutdown(sim, node_processes):
    track = build_track()
    odom = []
    odom_sub = rospy.Subscriber("/ground_truth/odom", Odometry, odom.append, queue_size=10)
    lanes = LaneListener()
    try:
        node = sim.start_node(timing_report_period_s=3600.0)  # only the line at shutdown
        node_processes.append(node)
        wait_until_node_ready(sim, node, SIM_IMAGE_TOPICS)
        rows = []
        for name, (lateral_m, heading_rad) in POSES.items():
            # northbound: the robot's left is world -x
            sim.set_start_pose(LANE_X_M - lateral_m, -2.0, math.pi / 2 + heading_rad)
            settled_s = sim.step(200)  # the robot settles on its wheels

            def measured_at_rest():  # 3 measurements of images taken after settling, and ground truth
                measured = lanes.since(settled_s + 1e-6)
                at_rest = odom and odom[-1].header.stamp.to_sec() > settled_s
                return measured[:3] if len(measured) >= 3 and at_rest else None

            measured = wait_until(
                measured_at_rest,
                lambda: f"{name}: 3 measurements on /conde_lane and ground truth after t = {settled_s:.3f} s\n"
                        f"--- node output:\n{node.output()}",
                between=lambda: sim.step(CAMERA_PERIOD_STEPS))
            pose = odom[-1].pose.pose
            yaw = 2 * math.atan2(pose.orientation.z, pose.orientation.w)  # flat ground
            where = track.locate([[pose.position.x, pose.position.y]])
            truth = (float(where["lateral"][0]), wrap(yaw - float(where["heading"][0])))
            rows += [(name, lateral_m, heading_rad, truth, lane) for lane in measured]

        table = "\n".join(f"{name}: placed ({lat:+.3f} m, {math.degrees(head):+.1f} deg), "
                          f"ground truth ({gt[0]:+.3f} m, {math.degrees(gt[1]):+.1f} deg), "
                          f"measured ({lane.lateral_offset_m:+.3f} m, {math.degrees(lane.heading_error_rad):+.1f} deg, "
                          f"confidence {lane.confidence:.1f})"
                          for name, lat, head, gt, lane in rows)
        print(table)  # shown with pytest -s
        for name, lateral_m, heading_rad, (gt_lateral_m, gt_heading_rad), lane in rows:
            misplaced = f"the robot is not where it was put\n{table}"
            assert abs(gt_lateral_m - lateral_m) < 0.01, misplaced
            assert abs(wrap(gt_heading_rad - heading_rad)) < math.radians(1.0), misplaced
            assert lane.confidence > 0, table
            assert abs(lane.lateral_offset_m - gt_lateral_m) < 0.02, table
            assert abs(wrap(lane.heading_error_rad - gt_heading_rad)) < math.radians(3.0), table
            assert lane.lane_index == 0 and abs(lane.lane_spacing_m - 0.782) < 0.01, table  # the right lane

        assert not node.matches(TIMING_LINE), "a timing line before shutdown with a 3600 s period"
        assert node.stop(), f"conde_tracking did not stop on SIGINT within 60 s\n{node.output()}"
        timing = node.matches(TIMING_LINE)
        assert len(timing) == 1, f"expected one timing line at shutdown\n{node.output()}"
        frames, mean_ms, max_ms = int(timing[0].group(1)), float(timing[0].group(2)), float(timing[0].group(3))
        received = len(lanes.since(0.0))
        assert frames >= received > 0  # one frame per published measurement
        assert 0 < mean_ms <= max_ms
    finally:
        odom_sub.unregister()
        lanes.close()
