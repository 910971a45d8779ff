#!/usr/bin/env python3
"""Checks of libgazebo_ros_depth_camera.so and libgazebo_ros_openni_kinect.so (see
depth_cameras.test) against known geometry: both cameras sit 0.2 m high, 0.8 m before the crate's
near face (0.4 m high, 1 m wide), 64 x 48 pixels, horizontal field of view 1 rad. The simulation is
stepped. With CONDE_SAVE_IMAGES=<folder> the images are written there as PNG to look at."""
import math

import numpy as np
import rospy
import rostest
from sensor_msgs import point_cloud2
from sensor_msgs.msg import CameraInfo, Image, PointCloud2

from stepped_sim import SettledFrameTest, write_png

CRATE_DISTANCE_M = 0.8
CAMERA_HEIGHT_M = 0.2
WIDTH_PX, HEIGHT_PX = 64, 48
FOCAL_PX = WIDTH_PX / (2.0 * math.tan(0.5))  # Gazebo's pinhole from the horizontal FOV
CX_PX, CY_PX = (WIDTH_PX - 1) / 2.0, (HEIGHT_PX - 1) / 2.0

TOPICS = {
    "rgb": ("/bot/depth_cam/rgb/image_raw", Image),
    "rgb_info": ("/bot/depth_cam/rgb/camera_info", CameraInfo),
    "depth": ("/bot/depth_cam/depth/image_raw", Image),
    "depth_info": ("/bot/depth_cam/depth/camera_info", CameraInfo),
    "points": ("/bot/depth_cam/depth/points", PointCloud2),
    # the Kinect's defaults
    "ir": ("/bot/kinect/ir/image_raw", Image),
    "ir_info": ("/bot/kinect/ir/camera_info", CameraInfo),
    "kinect_depth": ("/bot/kinect/depth/image_raw", Image),
    "kinect_depth_info": ("/bot/kinect/depth/camera_info", CameraInfo),
    "kinect_points": ("/bot/kinect/points", PointCloud2),
}


def depth_array(msg):
    return np.frombuffer(msg.data, dtype=np.float32).reshape(msg.height, msg.width)


def cloud_array(msg):
    points = point_cloud2.read_points(msg, field_names=("x", "y", "z"), skip_nans=False)
    return np.array(list(points), dtype=np.float64).reshape(msg.height, msg.width, 3)


def ground_depth_m(v):
    """z-depth at which row v (below the centre) meets the ground."""
    return CAMERA_HEIGHT_M * FOCAL_PX / (v - CY_PX)


class DepthCamerasTest(SettledFrameTest):
    """The messages of one frame after the cube settled."""
    NODE = "depth_cameras_test"
    TOPICS = TOPICS

    @classmethod
    def save_images(cls, folder):
        import cv2
        engine = rospy.get_param("/conde_sim/physics_engine", "engine")
        for name in ("rgb", "ir"):
            msg = cls.last[name]
            rgb = np.frombuffer(msg.data, dtype=np.uint8).reshape(msg.height, msg.width, 3)
            write_png(folder, f"depth_{engine}_{name}.png", rgb[:, :, ::-1], 8)
        for name in ("depth", "kinect_depth"):
            depth = depth_array(cls.last[name])
            grey = np.where(np.isfinite(depth), 255 - np.clip(depth / 2.0 * 255, 0, 255), 0).astype(np.uint8)
            grey[np.isnan(depth)] = 0
            image = cv2.cvtColor(grey, cv2.COLOR_GRAY2BGR)
            image[np.isnan(depth)] = (0, 0, 255)  # NaN in red
            write_png(folder, f"depth_{engine}_{name}.png", image, 8)

    def test_sizes_encodings_frames(self):
        for name, encoding, frame in (("rgb", "rgb8", "depth_link_optical"), ("depth", "32FC1", "depth_link_optical"),
                                      ("ir", "rgb8", "kinect_link_optical"),
                                      ("kinect_depth", "32FC1", "kinect_link_optical")):
            msg = self.last[name]
            self.assertEqual((msg.width, msg.height, msg.encoding), (WIDTH_PX, HEIGHT_PX, encoding), name)
            self.assertEqual(msg.header.frame_id, frame, name)
            bytes_per_pixel = 3 if encoding == "rgb8" else 4
            self.assertEqual(msg.step, WIDTH_PX * bytes_per_pixel, name)
            self.assertEqual(len(msg.data), msg.step * msg.height, name)
        for name, frame in (("points", "depth_link_optical"), ("kinect_points", "kinect_link_optical")):
            msg = self.last[name]
            self.assertEqual((msg.width, msg.height), (WIDTH_PX, HEIGHT_PX), f"{name}: organised like the image")
            self.assertEqual(msg.header.frame_id, frame)
            self.assertEqual([f.name for f in msg.fields], ["x", "y", "z", "rgb"])
            self.assertFalse(msg.is_dense, f"{name} has NaN points")

    def test_camera_infos(self):
        for name in ("rgb_info", "depth_info", "ir_info", "kinect_depth_info"):
            info = self.last[name]
            self.assertEqual((info.width, info.height), (WIDTH_PX, HEIGHT_PX), name)
            for got, want in zip(info.K, (FOCAL_PX, 0, CX_PX, 0, FOCAL_PX, CY_PX, 0, 0, 1)):
                self.assertAlmostEqual(got, want, places=6, msg=name)
            self.assertEqual(info.P[3], 0.0, f"{name}: a single camera has no baseline")
        self.assertEqual(self.last["depth_info"].header.frame_id, "depth_link_optical")

    def test_depth_of_the_crate_within_1cm(self):
        depth = depth_array(self.last["depth"])
        # rows that see the crate's face: |y| < 0.2 m at 0.8 m
        for v in range(int(CY_PX) - 8, int(CY_PX) + 9):
            for u in range(0, WIDTH_PX, 7):
                self.assertAlmostEqual(float(depth[v, u]), CRATE_DISTANCE_M, delta=0.01, msg=f"pixel ({u}, {v})")

    def test_points_lie_on_the_crate_face(self):
        cloud = cloud_array(self.last["points"])
        for v in range(int(CY_PX) - 8, int(CY_PX) + 9):
            for u in range(WIDTH_PX):
                x, y, z = cloud[v, u]
                self.assertAlmostEqual(z, CRATE_DISTANCE_M, delta=0.01, msg=f"point ({u}, {v}) z")
                self.assertAlmostEqual(x, (u - CX_PX) / FOCAL_PX * CRATE_DISTANCE_M, delta=0.01, msg=f"({u}, {v}) x")
                self.assertAlmostEqual(y, (v - CY_PX) / FOCAL_PX * CRATE_DISTANCE_M, delta=0.01, msg=f"({u}, {v}) y")

    def test_ground_below_the_cutoff_is_nan(self):
        depth = depth_array(self.last["depth"])
        cloud = cloud_array(self.last["points"])
        u = WIDTH_PX // 2
        for v in range(int(CY_PX) + 10, HEIGHT_PX):
            expected = ground_depth_m(v)
            if expected < 0.59:  # pointCloudCutoff 0.6 m
                self.assertTrue(math.isnan(depth[v, u]), f"row {v} ({expected:.3f} m) is below the cut-off")
                self.assertTrue(np.isnan(cloud[v, u]).all(), f"point row {v}")
            elif 0.61 < expected < CRATE_DISTANCE_M - 0.01:
                self.assertAlmostEqual(float(depth[v, u]), expected, delta=0.01, msg=f"ground at row {v}")
                self.assertAlmostEqual(cloud[v, u][2], expected, delta=0.01, msg=f"point row {v}")
        self.assertTrue(math.isnan(depth[HEIGHT_PX - 1, u]), "the bottom row sees the ground at 0.5 m")

    def test_kinect_beyond_the_max_cutoff_is_nan(self):
        depth = depth_array(self.last["kinect_depth"])
        cloud = cloud_array(self.last["kinect_points"])
        u = WIDTH_PX // 2
        self.assertTrue(math.isnan(depth[int(CY_PX), u]), "the crate (0.8 m) is beyond pointCloudCutoffMax 0.7 m")
        self.assertTrue(np.isnan(cloud[int(CY_PX), u]).all())
        self.assertTrue(math.isnan(depth[0, u]), "the sky (no return) is beyond the cut-off too")
        v = HEIGHT_PX - 1
        self.assertAlmostEqual(float(depth[v, u]), ground_depth_m(v), delta=0.01, msg="near ground has values")
        self.assertAlmostEqual(cloud[v, u][2], ground_depth_m(v), delta=0.01)

    def test_colours_of_image_and_cloud_agree(self):
        image = self.last["rgb"]
        rgb = np.frombuffer(image.data, dtype=np.uint8).reshape(HEIGHT_PX, WIDTH_PX, 3)
        centre = rgb[int(CY_PX), WIDTH_PX // 2]
        self.assertGreater(int(centre.max()), 0, "the crate is drawn")
        packed = list(point_cloud2.read_points(self.last["points"], field_names=("rgb",), skip_nans=False))
        word = np.array([packed[int(CY_PX) * WIDTH_PX + WIDTH_PX // 2][0]], dtype=np.float32).view(np.uint32)[0]
        self.assertEqual(((word >> 16) & 255, (word >> 8) & 255, word & 255), tuple(int(c) for c in centre))


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "depth_cameras", DepthCamerasTest)
