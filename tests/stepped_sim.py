"""Helpers for rostests that drive a paused conde_sim node by its step service (no sleeping on
the wall clock for simulated time; wall-clock waits only for message delivery, and none for a
message to the simulator: send() has it acknowledged)."""
import os
import time
import unittest

import rospy
from conde_common.delivery import AcknowledgedPublisher, subscribes
from conde_msgs.srv import StepSimulation
from geometry_msgs.msg import Twist

WALL_TIMEOUT_S = 60.0  # generous: the machine may be slow and busy


def twist(x_m_s=0.0, y_m_s=0.0, yaw_rate_rad_s=0.0):
    """A velocity command: forward and leftward speed [m/s], yaw rate [rad/s]."""
    msg = Twist()
    msg.linear.x, msg.linear.y, msg.angular.z = x_m_s, y_m_s, yaw_rate_rad_s
    return msg


def wait_for(predicate, what, timeout_s=WALL_TIMEOUT_S):
    """Polls `predicate` on the wall clock until it holds."""
    end = time.monotonic() + timeout_s
    while time.monotonic() < end and not rospy.is_shutdown():
        if predicate():
            return
        time.sleep(0.01)
    raise AssertionError(f"timed out after {timeout_s} s waiting for {what}")


class SteppedSim:
    """The step service of a node started with ~paused:=true."""

    def __init__(self, node="/conde_sim"):
        rospy.wait_for_service(node + "/step", timeout=WALL_TIMEOUT_S)
        self._step = rospy.ServiceProxy(node + "/step", StepSimulation)
        self.time_s = self._step(0).sim_time_s

    def step(self, steps):
        """Advances the simulation by `steps` physics steps; returns the simulated time."""
        response = self._step(steps)
        assert response.success, response.message
        self.time_s = response.sim_time_s
        return self.time_s

    def step_until(self, predicate, what, steps=10, timeout_s=WALL_TIMEOUT_S):
        """Steps `steps` at a time until `predicate()` holds. For what only arrives while simulated
        time runs and has no connection to wait for first (a TF listener subscribes in the
        background: messages published before it is connected are lost)."""
        def holds_or_step():
            if predicate():
                return True
            self.step(steps)
            return False

        wait_for(holds_or_step, f"{what} (stepping {steps} at a time)", timeout_s)
        return self.time_s

    def run(self, seconds, every_s=0.05, before_chunk=None, step_s=0.001):
        """Steps `seconds` of simulated time in chunks of `every_s`, calling `before_chunk()`
        before each one (to re-send a command like a driver node at 1 / every_s Hz)."""
        chunk = max(1, round(every_s / step_s))
        for _ in range(max(1, round(seconds / every_s))):
            if before_chunk:
                before_chunk()
            self.step(chunk)
        return self.time_s

    def run_received(self, seconds, latest_periods, every_s=0.05, step_s=0.001):
        """Steps `seconds` in chunks of `every_s` and, after each chunk, waits for the message of the
        last update of each Latest in `latest_periods` ([(Latest, update period [s])]). For messages
        that are counted: a node's publisher queue (often 10 messages) then holds at most one chunk's
        messages, so none is dropped however slowly this test receives them."""
        chunk = max(1, round(every_s / step_s))
        for _ in range(max(1, round(seconds / every_s))):
            self.step(chunk)
            for latest, period_s in latest_periods:
                latest.wait_until_stamped(self.time_s, period_s)
        return self.time_s


def connected(publisher_or_subscriber, what):
    """Waits until the node is connected to a test's publisher or subscriber."""
    wait_for(lambda: publisher_or_subscriber.get_num_connections() > 0, f"a connection on {what}")


DELIVERY_S = 0.3  # [s] wall time given to a message for a receiver that does not acknowledge it


def send(publisher, message, what, sim_node="/conde_sim"):
    """Publishes once the node listens. When the simulator subscribes to the topic, returns once it
    has received the message and its plugin has handled it (acknowledged delivery,
    conde_common.delivery): the next step sees it. Any other receiver (the referee, a driving node)
    gives no acknowledgement: the message gets DELIVERY_S of wall time to arrive."""
    connected(publisher, what)
    if subscribes(sim_node, publisher.resolved_name):
        acknowledged = AcknowledgedPublisher(publisher, sim_node)
        try:
            acknowledged.send(message)
        finally:
            acknowledged.close()
    else:
        publisher.publish(message)
        time.sleep(DELIVERY_S)


class Latest:
    """Keeps the messages of a topic."""

    def __init__(self, topic, msg_type):
        self.messages = []
        self.sub = rospy.Subscriber(topic, msg_type, self.messages.append, queue_size=100)
        self.topic = topic

    @classmethod
    def connected(cls, topic, msg_type):
        """A Latest of the topic once its publisher has connected to it."""
        latest = cls(topic, msg_type)
        connected(latest.sub, topic)
        return latest

    @property
    def last(self):
        return self.messages[-1] if self.messages else None

    def wait_until_stamped(self, time_s, period_s):
        """Waits for the message published at the last update not after `time_s`."""
        wait_for(lambda: self.messages and self.messages[-1].header.stamp.to_sec() >= time_s - period_s - 1e-6,
                 f"{self.topic} stamped {time_s:.3f} s")
        return self.messages[-1]


class ModelPoses:
    """Ground-truth model poses through /gazebo/get_model_state."""

    def __init__(self):
        from gazebo_msgs.srv import GetModelState
        rospy.wait_for_service("/gazebo/get_model_state", timeout=WALL_TIMEOUT_S)
        self._get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)

    def __call__(self, model):
        """The pose of `model` in the world (geometry_msgs/Pose)."""
        state = self._get_state(model, "")
        assert state.success, state.status_message
        return state.pose


def settled_frame(topics, settle_steps=200, seconds=0.3, every_s=0.1):
    """The camera tests' start: subscribes to `topics` ({name: (topic, type)}), lets the robot settle
    for `settle_steps` steps, runs `seconds` more and waits for the message of each topic's last
    update (`every_s` apart). Returns {name: Latest}."""
    sim = SteppedSim()
    latest = {name: Latest.connected(topic, msg_type) for name, (topic, msg_type) in topics.items()}
    sim.step(settle_steps)
    end_s = sim.run(seconds, every_s=every_s)
    for one in latest.values():
        one.wait_until_stamped(end_s, every_s)
    return latest


class SettledFrameTest(unittest.TestCase):
    """Base of the camera checks: the messages of one frame after the robot settled, in cls.last
    ({name: message}) and cls.topics ({name: Latest}). A subclass sets NODE and TOPICS, and writes
    its images in save_images(folder) when CONDE_SAVE_IMAGES names a folder."""
    NODE = "settled_frame_test"
    TOPICS = {}

    @classmethod
    def setUpClass(cls):
        rospy.init_node(cls.NODE)
        cls.topics = settled_frame(cls.TOPICS)  # the robot settles on the ground
        cls.last = {name: latest.last for name, latest in cls.topics.items()}
        folder = os.environ.get("CONDE_SAVE_IMAGES")
        if folder:
            cls.save_images(folder)

    @classmethod
    def save_images(cls, folder):
        pass


def write_png(folder, name, bgr, scale):
    """Writes an image `scale` times enlarged, pixels as squares, to look at."""
    import cv2
    cv2.imwrite(os.path.join(folder, name), cv2.resize(bgr, None, fx=scale, fy=scale, interpolation=cv2.INTER_NEAREST))
