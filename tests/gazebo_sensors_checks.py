#!/usr/bin/env python3
"""Checks of libgazebo_ros_range.so, libgazebo_ros_block_laser.so and the model-form
libgazebo_ros_imu.so (see gazebo_sensors.test) against known geometry: the robot's front face is
at x = 0.1 m, the crate's near face at x = 0.9 m, so the sonar and the block laser (at x = 0.1 m,
0.2 m high) see the crate 0.8 m ahead. The simulation is stepped."""
import math
import unittest

import rospy
import rostest
from sensor_msgs.msg import Imu, PointCloud, Range
from std_srvs.srv import Empty

from stepped_sim import Latest, SteppedSim

CRATE_DISTANCE_M = 0.8
GRAVITY_MPS2 = 9.81
BLOCK_YAWS_RAD = [-0.3, -0.15, 0.0, 0.15, 0.3]  # 5 horizontal rays over [-0.3, 0.3]
BLOCK_PITCHES_RAD = [-0.1, 0.0, 0.1]  # 3 vertical rays over [-0.1, 0.1]


# Topic, type and publishing period [s] of each sensor of the fixture.
SENSORS = {
    "sonar": ("/bot/sonar", Range, 0.1),
    "ir": ("/bot/ir", Range, 0.02),
    "block": ("/bot/block_cloud", PointCloud, 0.1),
    "imu": ("/bot/imu", Imu, 0.02),
}


class GazeboSensorsTest(unittest.TestCase):
    """One simulated second after the robot settled, every sensor's messages kept."""

    @classmethod
    def setUpClass(cls):
        rospy.init_node("gazebo_sensors_test")
        sim = SteppedSim()
        cls.topics = {name: Latest.connected(topic, msg_type) for name, (topic, msg_type, _) in SENSORS.items()}
        cls.start_s = sim.step(200)  # the cube settles on the ground
        # Counted below: each 0.1 s chunk's messages (5 of the 50 Hz sensors) are received before the
        # next chunk, as the plugins' publisher queues hold 10.
        cls.end_s = sim.run_received(1.0, [(cls.topics[name], period_s) for name, (_, _, period_s) in SENSORS.items()],
                                     every_s=0.1)

    def count(self, name):
        """Messages stamped in the simulated second (start_s, end_s]."""
        stamps = [m.header.stamp.to_sec() for m in self.topics[name].messages]
        return sum(1 for t in stamps if self.start_s + 1e-6 < t <= self.end_s + 1e-6)

    def test_rates_follow_sensor_and_plugin_rates(self):
        # sonar: sensor 20 Hz, plugin 10 Hz -> 10 Hz; ir 50 Hz; block laser 10 Hz; IMU updateRate 50 Hz
        for name, hz in (("sonar", 10), ("ir", 50), ("block", 10), ("imu", 50)):
            self.assertAlmostEqual(self.count(name), hz, delta=1, msg=f"{name} messages in one simulated second")

    def test_sonar_sees_the_crate(self):
        msg = self.topics["sonar"].last
        self.assertEqual(msg.header.frame_id, "sonar_link")
        self.assertEqual(msg.radiation_type, Range.ULTRASOUND)
        self.assertAlmostEqual(msg.field_of_view, 0.2, places=6)
        self.assertAlmostEqual(msg.min_range, 0.02, places=6)
        self.assertAlmostEqual(msg.max_range, 4.0, places=6)
        self.assertAlmostEqual(msg.range, CRATE_DISTANCE_M, delta=0.01)

    def test_infrared_sees_nothing_behind(self):
        msg = self.topics["ir"].last
        self.assertEqual(msg.header.frame_id, "ir_link")  # frameName defaults to the link
        self.assertEqual(msg.radiation_type, Range.INFRARED)
        self.assertAlmostEqual(msg.max_range, 2.0, places=6)
        self.assertTrue(math.isinf(msg.range) and msg.range > 0, f"range {msg.range}: nothing within 2 m (REP 117)")

    def test_block_laser_points_lie_on_the_crate_face(self):
        msg = self.topics["block"].last
        self.assertEqual(msg.header.frame_id, "block_link")  # "/block_link" without its leading '/'
        self.assertEqual(len(msg.points), len(BLOCK_YAWS_RAD) * len(BLOCK_PITCHES_RAD))
        self.assertEqual([c.name for c in msg.channels], ["intensity"])
        self.assertEqual(len(msg.channels[0].values), len(msg.points))
        k = 0
        for pitch in BLOCK_PITCHES_RAD:  # rows from the lowest, columns from the right (-yaw)
            for yaw in BLOCK_YAWS_RAD:
                p = msg.points[k]
                expected = (CRATE_DISTANCE_M, CRATE_DISTANCE_M * math.tan(yaw),
                            CRATE_DISTANCE_M * math.tan(pitch) / math.cos(yaw))
                for got, want, axis in zip((p.x, p.y, p.z), expected, "xyz"):
                    self.assertAlmostEqual(got, want, delta=0.01, msg=f"point {k} {axis} (yaw {yaw}, pitch {pitch})")
                k += 1

    def test_model_imu_measures_gravity_at_rest(self):
        msg = self.topics["imu"].last
        self.assertEqual(msg.header.frame_id, "imu_link")
        self.assertAlmostEqual(msg.linear_acceleration.z, GRAVITY_MPS2, delta=0.1)
        self.assertAlmostEqual(msg.linear_acceleration.x, 0.0, delta=0.1)
        self.assertAlmostEqual(msg.orientation.w, 1.0, delta=1e-3)
        self.assertAlmostEqual(msg.angular_velocity.z, 0.0, delta=1e-2)

    def test_imu_service_answers(self):
        rospy.wait_for_service("/bot/imu_service", timeout=60)
        rospy.ServiceProxy("/bot/imu_service", Empty)()


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "gazebo_sensors", GazeboSensorsTest)
