#!/usr/bin/env python3
"""Major Alvega's two wide-angle cameras (major_cameras.test: conde_major's major.launch with its
cameras, paused): each publishes rgb8 images of its size and a CameraInfo, exactly 30 frames per
simulated second, stamped in its optical frame. The simulation is stepped."""
import unittest

import numpy as np
import rospy
import rostest
from sensor_msgs.msg import CameraInfo, Image

from stepped_sim import Latest, SteppedSim, connected, wait_for

# name -> (image topic, info topic, optical frame, width, height) as the original's topics
CAMERAS = {
    "tracking": ("/major_tracking_camera/image_raw", "/major_tracking_camera/camera_info",
                 "camera_link_optical", 160, 120),
    "top": ("/major_top_camera/image_raw", "/major_top_camera/top_camera_info",
            "top_camera_link_optical", 320, 240),
}
RATE_HZ = 30
STEP_S = 0.001


class MajorCameraTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("major_camera_checks")
        cls.engine = rospy.get_param("~physics_engine")
        cls.sim = SteppedSim()
        cls.images = {name: Latest(topics[0], Image) for name, topics in CAMERAS.items()}
        cls.infos = {name: Latest(topics[1], CameraInfo) for name, topics in CAMERAS.items()}
        for name, topics in CAMERAS.items():
            connected(cls.images[name].sub, topics[0])
            connected(cls.infos[name].sub, topics[1])

    def test_images_at_30_hz_of_sim_time_with_size_encoding_and_frame(self):
        self.sim.step(100)  # past the start
        start_s = self.sim.time_s
        # 10 ms chunks: at most one frame per camera per chunk, each chunk's frame received (all but
        # perhaps the newest) before the next, so the node's publisher queues (2) never overflow; one
        # second and a bit of simulated time. A frame is at most 34 steps after the one before.
        topics = list(self.images.values()) + list(self.infos.values())
        self.sim.run_received(1.05, [(latest, 0.034) for latest in topics], every_s=0.01)
        end_s = start_s + 1.0
        for name, (image_topic, info_topic, frame, width, height) in CAMERAS.items():
            images, infos = self.images[name], self.infos[name]
            wait_for(lambda: images.last and images.last.header.stamp.to_sec() >= end_s,
                     f"{image_topic} past {end_s:.3f} s")
            wait_for(lambda: infos.last and infos.last.header.stamp.to_sec() >= end_s,
                     f"{info_topic} past {end_s:.3f} s")
            in_second = [m for m in images.messages if start_s <= m.header.stamp.to_sec() < end_s]
            stamps = [m.header.stamp.to_sec() for m in in_second]
            print(f"[{self.engine}] {image_topic}: {len(in_second)} images stamped in [{start_s:.3f}, {end_s:.3f}) s, "
                  f"{in_second[-1].width}x{in_second[-1].height} {in_second[-1].encoding} in "
                  f"{in_second[-1].header.frame_id}", flush=True)
            self.assertEqual(len(in_second), RATE_HZ, image_topic)
            gaps = np.diff(stamps)
            self.assertTrue(np.all((gaps > 0.033 - 1e-6) & (gaps < 0.034 + 1e-6)), f"{image_topic}: {gaps}")
            for m in in_second:
                self.assertEqual((m.width, m.height, m.encoding, m.header.frame_id), (width, height, "rgb8", frame))
                self.assertEqual(m.step, 3 * width)
                self.assertEqual(len(m.data), 3 * width * height)
            pixels = np.frombuffer(in_second[-1].data, dtype=np.uint8)
            self.assertGreater(int(pixels.max()) - int(pixels.min()), 50, f"{image_topic}: a blank image")
            info = infos.last
            self.assertEqual((info.width, info.height, info.header.frame_id), (width, height, frame), info_topic)


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "major_cameras", MajorCameraTest)
