"""Renders top-camera images of the signalling panel with a running conde_sim (paused) and a
signalling_panel_controller in service mode: ROS plumbing shared by render_panel_dataset and
semaphore_accuracy. Call connect() (or rospy.init_node) first."""
import threading
import time

import numpy as np
import rosgraph
import rospy
from conde_msgs.srv import SetPanelSignal, SetStartPose, StepSimulation
from sensor_msgs.msg import Image
from std_srvs.srv import Empty

from conde_common.images import image_to_array

TOP_CAMERA_TOPIC = "/conde_camera_signalling_panel/image_raw"
SET_SIGNAL_SERVICE = "/signalling_panel_controller/set_signal"
SET_START_POSE_SERVICE = "/conde_sim/set_start_pose"
STEP_SERVICE = "/conde_sim/step"
PAUSE_SERVICE = "/conde_sim/pause_physics"

# The start zone of the robot at the competition start (metres, radians), east lane heading north.
START_ZONE_X_M = (1.95, 2.35)
START_ZONE_Y_M = (-0.5, -0.25)
START_ZONE_YAW_RAD = (np.radians(80.0), np.radians(100.0))
START_POSE = (2.14, -0.33, 1.5708)

SETTLE_STEPS = 40   # 1 ms steps after a new pose / signal before the image is taken
STEPS_PER_TRY = 40  # one camera frame is 33.3 ms of sim time at 30 Hz
DISPLAY_DELIVERY_S = 0.3  # wall-clock time for a new panel picture to reach the simulator


def connect(node_name, timeout_s=60.0):
    """rospy.init_node once the ROS master answers; RuntimeError naming its URI otherwise."""
    deadline = time.monotonic() + timeout_s
    while not rosgraph.is_master_online():
        if time.monotonic() > deadline:
            raise RuntimeError("no ROS master at %s after %.0f s" % (rosgraph.get_master_uri(), timeout_s))
        time.sleep(0.2)
    rospy.init_node(node_name, anonymous=True, disable_signals=True)


class SimPanelCamera:
    """set_signal(name), set_pose(x_m, y_m, yaw_rad), next_image() -> (RGB array, Image message).
    With panel=False no panel controller in service mode is needed (no set_signal)."""

    def __init__(self, image_topic=TOP_CAMERA_TOPIC, timeout_s=60.0, panel=True):
        services = (SET_START_POSE_SERVICE, STEP_SERVICE, PAUSE_SERVICE) + ((SET_SIGNAL_SERVICE,) if panel else ())
        for service in services:
            try:
                rospy.wait_for_service(service, timeout=timeout_s)
            except rospy.ROSException:
                raise RuntimeError("service %s did not come up within %.0f s: start conde_sim and "
                                   "signalling_panel_controller (_mode:=service)" % (service, timeout_s))
        self.set_signal_service = rospy.ServiceProxy(SET_SIGNAL_SERVICE, SetPanelSignal) if panel else None
        self.set_pose_service = rospy.ServiceProxy(SET_START_POSE_SERVICE, SetStartPose)
        self.step_service = rospy.ServiceProxy(STEP_SERVICE, StepSimulation)
        rospy.ServiceProxy(PAUSE_SERVICE, Empty)()  # images come only from the steps below
        self.image_topic = image_topic
        self.condition = threading.Condition()
        self.last_image = None
        self.subscriber = rospy.Subscriber(image_topic, Image, self._on_image, queue_size=5)

    def _on_image(self, msg):
        with self.condition:
            self.last_image = msg
            self.condition.notify_all()

    def set_signal(self, name, delivery_s=DISPLAY_DELIVERY_S):
        """Shows a signal. The controller publishes the picture on a latched topic that the
        simulator's display plugin reads between steps; nothing reports its arrival, so this
        waits delivery_s of wall-clock time for it (the simulation is paused meanwhile)."""
        response = self.set_signal_service(name)
        if not response.success:
            raise RuntimeError("%s %r failed: %s" % (SET_SIGNAL_SERVICE, name, response.message))
        time.sleep(delivery_s)

    def set_pose(self, x_m, y_m, yaw_rad):
        response = self.set_pose_service("", x_m, y_m, yaw_rad)
        if not response.success:
            raise RuntimeError("%s (%.3f, %.3f, %.3f) failed: %s"
                               % (SET_START_POSE_SERVICE, x_m, y_m, yaw_rad, response.message))

    def next_image(self, settle_steps=SETTLE_STEPS, tries=25, wait_s=5.0):
        """Steps settle_steps, then steps until an image captured after them arrives (by its
        stamp, so a late image of the previous pose is never taken); (RGB uint8 array, msg)."""
        settled_s = self.step_service(settle_steps).sim_time_s

        def is_new():
            return self.last_image is not None and self.last_image.header.stamp.to_sec() > settled_s - 1e-6

        for _ in range(tries):
            self.step_service(STEPS_PER_TRY)
            with self.condition:
                if self.condition.wait_for(is_new, timeout=wait_s):
                    return image_to_array(self.last_image), self.last_image
        raise RuntimeError("no image on %s after %d steps" % (self.image_topic, settle_steps + tries * STEPS_PER_TRY))
