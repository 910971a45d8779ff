#!/usr/bin/env python3
"""Checks of the IMU sensor plugin with noise (see imu.test). The simulation is stepped."""
import math
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu

from stepped_sim import Latest, SteppedSim

NOISE_STDDEV = 0.05  # imu_noise in imu.test


def quaternion(q):
    return (q.w, q.x, q.y, q.z)


def angle_between_rad(a, b):
    """Rotation angle between two unit quaternions (w, x, y, z)."""
    dot = abs(sum(x * y for x, y in zip(a, b)))
    return 2.0 * math.acos(min(1.0, dot))


class ImuNoiseTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("imu_test")
        cls.sim = SteppedSim()
        cls.imu = Latest.connected("/imu", Imu)
        cls.truth = Latest.connected("/ground_truth/odom", Odometry)
        cls.sim.step(1000)  # 100 IMU messages (100 Hz), 50 of the ground truth (Conde stands still)
        cls.sim.step_until(lambda: len(cls.imu.messages) >= 100, "100 IMU messages")

    def test_orientation_is_a_unit_quaternion(self):
        norms = [math.sqrt(sum(c * c for c in quaternion(m.orientation))) for m in self.imu.messages]
        worst = max(abs(n - 1.0) for n in norms)
        self.assertLess(worst, 1e-9, f"|q| - 1 up to {worst:.3g} over {len(norms)} messages")

    def test_orientation_noise_is_a_small_rotation(self):
        still = quaternion(self.truth.messages[-1].pose.pose.orientation)  # Conde stands still
        angles = [angle_between_rad(quaternion(m.orientation), still) for m in self.imu.messages]
        # Rotation vectors with three N(0, sigma) components: angle ~ sigma * chi(3), mean 1.6 sigma.
        mean = sum(angles) / len(angles)
        self.assertGreater(mean, 0.8 * NOISE_STDDEV, "no orientation noise")
        self.assertLess(mean, 2.5 * NOISE_STDDEV, "orientation noise larger than asked")

    def test_rates_are_noisy_with_the_given_stddev(self):
        rates = [m.angular_velocity.z for m in self.imu.messages]
        mean = sum(rates) / len(rates)
        stddev = math.sqrt(sum((r - mean) ** 2 for r in rates) / (len(rates) - 1))
        self.assertAlmostEqual(stddev, NOISE_STDDEV, delta=0.4 * NOISE_STDDEV)


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "imu", ImuNoiseTest)
