#!/usr/bin/env python3
"""Checks of libgazebo_ros_multicamera.so (see multicamera.test) against known geometry: the stereo
pair sits 0.2 m high, its cameras 0.1 m apart (left at y +0.05 m, right at -0.05 m), 1.0 m before
the near face of a red post 0.1 m wide centred between them; 160 x 120 pixels, horizontal field of
view 1 rad. The simulation is stepped. With CONDE_SAVE_IMAGES=<folder> the images are written there
as PNG to look at."""
import math

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import CameraInfo, Image

from stepped_sim import SettledFrameTest, wait_for, write_png

POST_DEPTH_M = 1.0
BASELINE_M = 0.1
WIDTH_PX, HEIGHT_PX = 160, 120
FOCAL_PX = WIDTH_PX / (2.0 * math.tan(0.5))  # Gazebo's pinhole from the horizontal FOV: 146.5 px
CX_PX, CY_PX = (WIDTH_PX - 1) / 2.0, (HEIGHT_PX - 1) / 2.0
FRAME = "stereo_left_optical"

TOPICS = {
    "left": ("/bot/stereo/left/image_raw", Image),
    "left_info": ("/bot/stereo/left/camera_info", CameraInfo),
    "right": ("/bot/stereo/right/image_raw", Image),
    "right_info": ("/bot/stereo/right/camera_info", CameraInfo),
    # the second sensor: the plugin's defaults (cameraName "camera")
    "pair_left": ("/bot/camera/left/image_raw", Image),
    "pair_left_info": ("/bot/camera/left/camera_info", CameraInfo),
    "pair_right": ("/bot/camera/right/image_raw", Image),
    "pair_right_info": ("/bot/camera/right/camera_info", CameraInfo),
}


def rgb_array(msg):
    return np.frombuffer(msg.data, dtype=np.uint8).reshape(msg.height, msg.width, 3)


def red_columns(msg, row):
    """Columns of `row` that see the red post (shaded: dark red, grey ground, blue sky around it)."""
    pixels = rgb_array(msg)[row].astype(int)
    return np.nonzero((pixels[:, 0] > 50) & (pixels[:, 0] > 2 * pixels[:, 1]) & (pixels[:, 0] > 2 * pixels[:, 2]))[0]


def post_centre_px(msg):
    """The post's centre column, from its two edges averaged over the rows around the centre."""
    centres = []
    for row in range(int(CY_PX) - 10, int(CY_PX) + 11):
        columns = red_columns(msg, row)
        assert len(columns) > 0, f"row {row} of {msg.header.frame_id} does not see the post"
        assert columns[-1] - columns[0] + 1 == len(columns), f"row {row}: the post is one run of pixels"
        centres.append((columns[0] + columns[-1]) / 2.0)
    return float(np.mean(centres))


class MultiCameraTest(SettledFrameTest):
    """The messages of one frame after the cube settled."""
    NODE = "multicamera_test"
    TOPICS = TOPICS

    @classmethod
    def save_images(cls, folder):
        engine = rospy.get_param("/conde_sim/physics_engine", "engine")
        for name in ("left", "right", "pair_right"):
            write_png(folder, f"multicamera_{engine}_{name}.png", rgb_array(cls.last[name])[:, :, ::-1], 4)

    def test_images_sizes_encodings_frames(self):
        for name, size, encoding, frame in (("left", (WIDTH_PX, HEIGHT_PX), "rgb8", FRAME),
                                            ("right", (WIDTH_PX, HEIGHT_PX), "rgb8", FRAME),
                                            ("pair_left", (32, 24), "mono8", "wide_link_optical"),
                                            ("pair_right", (48, 36), "rgb8", "wide_link_optical")):
            msg = self.last[name]
            self.assertEqual((msg.width, msg.height, msg.encoding), size + (encoding,), name)
            self.assertEqual(msg.header.frame_id, frame, f"{name}: both cameras in the left optical frame")
            self.assertEqual(len(msg.data), msg.step * msg.height, name)
            info = self.last[name + "_info"]
            self.assertEqual((info.width, info.height), size, name)
            self.assertEqual(info.header.frame_id, frame, name)
            # the info is published right after its image: it may still be on its way
            wait_for(lambda: msg.header.stamp in self.stamps(name + "_info"), f"{name}: an info stamped with its image")
        wait_for(lambda: self.last["left"].header.stamp in self.stamps("right"), "both cameras capturing at one time")

    def stamps(self, name):
        return [m.header.stamp for m in self.topics[name].messages]

    def test_camera_infos_of_the_pair(self):
        left, right = self.last["left_info"], self.last["right_info"]
        for name, info in (("left", left), ("right", right)):
            for got, want in zip(info.K, (FOCAL_PX, 0, CX_PX, 0, FOCAL_PX, CY_PX, 0, 0, 1)):
                self.assertAlmostEqual(got, want, places=6, msg=name)
            want_p = [FOCAL_PX, 0, CX_PX, 0, FOCAL_PX, CY_PX, 0, 0, 0, 1, 0]  # all of P but P[3]
            for got, want in zip(list(info.P[:3]) + list(info.P[4:]), want_p):
                self.assertAlmostEqual(got, want, places=6, msg=name)
        self.assertEqual(left.P[3], 0.0, "the left camera is the reference")
        self.assertAlmostEqual(right.P[3], -FOCAL_PX * BASELINE_M, places=9, msg="P[3] = -fx * hackBaseline")
        self.assertEqual(list(left.D), [-0.01, 0.0, 0.0, 0.0, 0.0], "each camera its own <distortion>")
        self.assertEqual(list(right.D), [0.0] * 5)
        # The second pair: each camera its own field of view; no hackBaseline, P[3] 0 as in Gazebo.
        pair_right = self.last["pair_right_info"]
        self.assertAlmostEqual(pair_right.K[0], 48 / (2 * math.tan(0.75)), places=6)
        self.assertAlmostEqual(self.last["pair_left_info"].K[0], 32 / (2 * math.tan(1.047 / 2)), places=6)
        self.assertEqual(pair_right.P[3], 0.0)

    def test_post_where_the_pinhole_puts_it(self):
        # The post's centre is 0.05 m right of the left camera and 0.05 m left of the right one.
        offset_px = FOCAL_PX * (BASELINE_M / 2) / POST_DEPTH_M
        self.assertAlmostEqual(post_centre_px(self.last["left"]), CX_PX + offset_px, delta=1.0)
        self.assertAlmostEqual(post_centre_px(self.last["right"]), CX_PX - offset_px, delta=1.0)

    def test_disparity_is_fx_baseline_over_depth(self):
        disparity_px = post_centre_px(self.last["left"]) - post_centre_px(self.last["right"])
        expected_px = FOCAL_PX * BASELINE_M / POST_DEPTH_M  # 14.65 px
        self.assertAlmostEqual(disparity_px, expected_px, delta=1.0)
        # What a stereo node computes from the two camera infos alone.
        tx = self.last["right_info"].P[3]  # -fx * baseline
        self.assertAlmostEqual(-tx / disparity_px, POST_DEPTH_M, delta=0.07, msg="depth from disparity [m]")

    def test_images_differ_only_where_the_views_do(self):
        left, right = rgb_array(self.last["left"]).astype(int), rgb_array(self.last["right"]).astype(int)
        self.assertGreater(np.abs(left - right).max(), 100, "the two cameras see the post in different places")
        # Far ground rows (near the horizon) look alike from 0.1 m apart: same colour everywhere.
        row = int(CY_PX) + 40
        self.assertLess(np.abs(left[row, :20].mean(axis=0) - right[row, :20].mean(axis=0)).max(), 10)


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "multicamera", MultiCameraTest)
