#!/usr/bin/env python3
"""Conde's cameras through ROS (see cameras.test): rates in sim time, CameraInfo, optical frames
in TF, and the signalling-panel monitors seen by the top camera."""
import functools
import math
import time
import unittest
import xml.etree.ElementTree as ET

import numpy as np
import rospy
import rostest
import tf2_ros
from conde_msgs.srv import SetPanelSignal
from sensor_msgs.msg import CameraInfo, Image
from std_srvs.srv import Empty

from conde_msgs.srv import StepSimulation

import stepped_sim

WALL_TIMEOUT_S = 90.0  # generous: the machine may be slow and busy
FRAME_S = 1.0 / 30.0

# name -> (image topic, info topic, optical frame, sensor link in the URDF)
CAMERAS = {
    "left": ("/conde_camera_tracking_left/image_raw", "/conde_camera_tracking_left/camera_info_left",
             "camera_tracking_left_optical", "camera_tracking_left_link"),
    "right": ("/conde_camera_tracking_right/image_raw", "/conde_camera_tracking_right/camera_right_info",
              "camera_tracking_right_optical", "camera_tracking_right_link"),
    "top": ("/conde_camera_signalling_panel/image_raw", "/conde_camera_signalling_panel/camera_info_top",
            "camera_signalling_panel_optical", "camera_signalling_panel_link"),
}


wait_for = functools.partial(stepped_sim.wait_for, timeout_s=WALL_TIMEOUT_S)


def as_array(msg):
    return np.frombuffer(msg.data, dtype=np.uint8).reshape(msg.height, msg.width, 3)


def count_colour(image, colour):
    """Pixels close to a saturated colour: 'red' or 'green'."""
    r, g, b = (image[:, :, i].astype(int) for i in range(3))
    if colour == "red":
        return int(np.sum((r > 150) & (g < 80) & (b < 80)))
    return int(np.sum((g > 150) & (r < 80) & (b < 80)))


def camera_sensors_in_urdf(urdf_xml):
    """link -> <sensor> element of each camera in the robot description."""
    root = ET.fromstring(urdf_xml)
    return {g.get("reference"): s for g in root.findall("gazebo") for s in g.findall("sensor")
            if s.get("type") == "camera"}


class CameraTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("camera_checks")

    def collect(self, topic, msg_type, count):
        msgs = []
        sub = rospy.Subscriber(topic, msg_type, msgs.append, queue_size=100)
        wait_for(lambda: len(msgs) >= count, f"{count} messages on {topic}")
        sub.unregister()
        return msgs

    def test_images_come_at_30_hz_of_sim_time(self):
        # Paused and stepped one frame (34 steps) at a time, each camera's image received before the
        # next: an image publisher's queue holds 2, so a busy machine running free dropped frames.
        latest = {name: stepped_sim.Latest.connected(topic, Image) for name, (topic, _, _, _) in CAMERAS.items()}
        pause = rospy.ServiceProxy("/conde_sim/pause_physics", Empty)
        pause.wait_for_service(WALL_TIMEOUT_S)
        pause()
        try:
            sim = stepped_sim.SteppedSim()
            start_s = sim.time_s
            sim.run_received(13 * 0.034, [(one, 0.034) for one in latest.values()], every_s=0.034)
        finally:
            rospy.ServiceProxy("/conde_sim/unpause_physics", Empty)()
            for one in latest.values():
                one.sub.unregister()
        for name, (_, _, frame, _) in CAMERAS.items():
            msgs = [m for m in latest[name].messages if m.header.stamp.to_sec() > start_s][-12:]
            self.assertEqual(len(msgs), 12, name)
            stamps = [m.header.stamp.to_sec() for m in msgs]
            gaps = [b - a for a, b in zip(stamps, stamps[1:])]
            # Every frame comes (none dropped: each was received before the next step), 33 or 34
            # steps of 1 ms after the one before.
            for gap in gaps:
                self.assertIn(round(gap * 1000), (33, 34), f"{name}: two images {gap:.4f} s apart: {gaps}")
            # Over many frames the rate is exactly 30 Hz: frame k at step round(k * 1000 / 30).
            for stamp in stamps:
                k = round(stamp / FRAME_S)
                self.assertLess(abs(stamp - round(k * 1000 / 30) / 1000), 1e-6, f"{name}: stamp {stamp} off schedule")
            self.assertEqual(msgs[-1].header.frame_id, frame)
            self.assertEqual(msgs[-1].encoding, "rgb8")

    def test_camera_info_matches_the_urdf(self):
        sensors = camera_sensors_in_urdf(rospy.get_param("/robot_description"))
        for name, (image_topic, info_topic, frame, link) in CAMERAS.items():
            sensor = sensors[link]
            camera = sensor.find("camera")
            width = int(camera.find("image/width").text)
            height = int(camera.find("image/height").text)
            hfov = float(camera.find("horizontal_fov").text)
            d = camera.find("distortion")
            k1, k2, k3, p1, p2 = (float(d.find(k).text) for k in ("k1", "k2", "k3", "p1", "p2"))
            info = self.collect(info_topic, CameraInfo, 1)[-1]
            image = self.collect(image_topic, Image, 1)[-1]
            fx = width / (2 * math.tan(hfov / 2))
            self.assertEqual((info.width, info.height), (width, height), name)
            self.assertEqual((image.width, image.height), (width, height), name)
            self.assertEqual(info.header.frame_id, frame)
            self.assertEqual(info.distortion_model, "plumb_bob")
            np.testing.assert_allclose(info.K, [fx, 0, (width - 1) / 2, 0, fx, (height - 1) / 2, 0, 0, 1], atol=1e-9)
            np.testing.assert_allclose(info.D, [k1, k2, p1, p2, k3], atol=1e-15)
            self.assertNotEqual(k1, 0.0, f"{name}: the Conde cameras carry the original's distortion")

    def test_optical_frames_are_in_tf(self):
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        for name, (_, _, frame, link) in CAMERAS.items():
            wait_for(lambda: buffer.can_transform("base_footprint", frame, rospy.Time(0)), f"TF to {frame}")
            t = buffer.lookup_transform(link, frame, rospy.Time(0)).transform
            # REP 103: optical z (forward) is the link's x, optical x (right) is the link's -y.
            q = [t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w]
            np.testing.assert_allclose(np.abs(q), [0.5, 0.5, 0.5, 0.5], atol=1e-6, err_msg=name)

    def test_ground_cameras_see_the_lane_lines(self):
        for name in ("left", "right"):
            image = as_array(self.collect(CAMERAS[name][0], Image, 1)[-1])
            white = np.sum(np.all(image > 200, axis=2))
            dark = np.sum(np.all(image < 60, axis=2))
            self.assertGreater(white, 50, f"{name}: no white line pixels")
            self.assertGreater(dark, image.shape[0] * image.shape[1] // 4, f"{name}: no dark track")

    def test_panel_signal_reaches_the_top_camera_within_one_frame(self):
        top_topic = CAMERAS["top"][0]
        set_signal = rospy.ServiceProxy("/signalling_panel_controller/set_signal", SetPanelSignal)
        set_signal.wait_for_service(WALL_TIMEOUT_S)
        pause = rospy.ServiceProxy("/conde_sim/pause_physics", Empty)
        unpause = rospy.ServiceProxy("/conde_sim/unpause_physics", Empty)
        step = rospy.ServiceProxy("/conde_sim/step", StepSimulation)
        frames = []
        sub = rospy.Subscriber(top_topic, Image, frames.append, queue_size=100)
        try:
            self.assertTrue(set_signal("forward").success)
            wait_for(lambda: frames and count_colour(as_array(frames[-1]), "green") > 150,
                     "a green arrow on the monitor")
            pause()
            time.sleep(0.5)  # let frames already on the wire arrive
            self.assertTrue(set_signal("stop").success)
            # The simulator takes the new panel image between steps while paused; give the
            # message time to arrive (no sim time passes meanwhile).
            time.sleep(1.0)
            seen = len(frames)
            self.assertTrue(step(34).success)  # 34 steps of 1 ms hold exactly one frame at 30 Hz
            wait_for(lambda: len(frames) > seen, "the next top-camera frame")
            image = as_array(frames[seen])
            self.assertGreater(count_colour(image, "red"), 150, "the stop sign is not on the monitor one frame later")
            self.assertLess(count_colour(image, "green"), 20, "the old arrow is still on the monitor")
        finally:
            sub.unregister()
            unpause()


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "camera_checks", CameraTest)
