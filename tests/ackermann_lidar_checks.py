#!/usr/bin/env python3
"""Wiring of the Ackermann drive and LiDAR plugins with a real roscore (ackermann_lidar.test):
two namespaced cars, each answering only its own topics; the LiDAR sees the wall at its distance
with a header that matches the ranges; the command timeout brakes. The simulation is stepped."""
import math
import unittest

import rospy
import rostest
import tf2_ros
from conde_msgs.msg import AckermannDriveStamped
from geometry_msgs.msg import Twist
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState, LaserScan

from stepped_sim import Latest, SteppedSim, connected, send, wait_for

WALL_FACE_X_M = 3.0          # lidar_wall.world.yaml
LASER_X_M = 0.27             # ackermann_car.urdf.xacro: laser_joint, ahead of base_footprint
ODOM_PERIOD_S = 0.02         # plugin updateRate 50 Hz


def position(odom):
    p = odom.pose.pose.position
    return p.x, p.y


def distance(a, b):
    return math.hypot(a[0] - b[0], a[1] - b[1])


class AckermannLidarTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("ackermann_lidar_checks")
        cls.sim = SteppedSim()
        cls.truth = {car: Latest(f"/{car}/ground_truth/odom", Odometry) for car in ("car1", "car2")}
        for latest in cls.truth.values():
            connected(latest.sub, latest.topic)
        cls.sim.step(100)
        for latest in cls.truth.values():
            latest.wait_until_stamped(cls.sim.time_s, ODOM_PERIOD_S)

    def truth_now(self, car):
        return self.truth[car].wait_until_stamped(self.sim.time_s, ODOM_PERIOD_S)

    def test_lidar_sees_the_wall_and_header_matches_ranges(self):
        scans = Latest("/car1/scan", LaserScan)
        other = Latest("/car2/scan", LaserScan)
        connected(scans.sub, "/car1/scan")
        connected(other.sub, "/car2/scan")
        for _ in range(16):  # one scan (40 Hz) per 25 steps; the sensor's queue keeps only the newest
            self.sim.step(25)
            scans.wait_until_stamped(self.sim.time_s, 0.0)
            other.wait_until_stamped(self.sim.time_s, 0.0)
        scans.sub.unregister()
        other.sub.unregister()
        scans.messages[:] = scans.messages[-16:]
        first = scans.messages[0]
        self.assertEqual(first.header.frame_id, "car1/laser")
        self.assertEqual(other.messages[0].header.frame_id, "car2/laser")
        self.assertEqual(len(first.ranges), 1081)
        self.assertAlmostEqual(first.angle_min, -2.35619449, places=5)
        self.assertAlmostEqual(first.angle_max, 2.35619449, places=5)
        self.assertAlmostEqual(first.angle_min + 1080 * first.angle_increment, first.angle_max, places=5)
        self.assertAlmostEqual(first.range_min, 0.06, places=6)
        self.assertAlmostEqual(first.range_max, 10.0, places=6)
        self.assertAlmostEqual(first.scan_time, 0.025, places=6)
        stamps = [s.header.stamp.to_sec() for s in scans.messages]
        for a, b in zip(stamps, stamps[1:]):
            self.assertAlmostEqual(b - a, 0.025, places=6)  # sim time of each scan, 40 Hz

        # Where car1's LiDAR is (the other tests move the car, straight along x).
        pose = self.truth_now("car1").pose.pose
        yaw = 2.0 * math.atan2(pose.orientation.z, pose.orientation.w)
        laser_x = pose.position.x + LASER_X_M * math.cos(yaw)
        laser_y = pose.position.y + LASER_X_M * math.sin(yaw)
        # Centre beam: the wall ahead (mean of 16 noisy scans, noise 0.01 m).
        expected_m = (WALL_FACE_X_M - laser_x) / math.cos(yaw)
        centre = [s.ranges[540] for s in scans.messages]
        self.assertAlmostEqual(sum(centre) / len(centre), expected_m, delta=0.01)
        # Every beam that meets the wall reads the distance along its own angle; the others
        # (open floor) read +inf.
        checked = 0
        for i, r in enumerate(first.ranges):
            angle = first.angle_min + i * first.angle_increment + yaw
            along = (WALL_FACE_X_M - laser_x) / math.cos(angle) if math.cos(angle) > 1e-6 else math.inf
            wall_y = laser_y + along * math.sin(angle) if math.isfinite(along) else math.inf
            if abs(wall_y) < 0.55:
                self.assertAlmostEqual(r, along, delta=0.04, msg=f"beam {i}")
                checked += 1
            elif abs(wall_y) > 0.65:
                self.assertTrue(math.isinf(r), f"beam {i} at {angle:.3f} rad reads {r}")
        self.assertGreater(checked, 40)
        # car2 (3 m to the right) has nothing ahead.
        self.assertTrue(math.isinf(other.messages[-1].ranges[540]))

    def test_each_car_answers_only_its_own_topics(self):
        drive = rospy.Publisher("/car1/ackermann_cmd", AckermannDriveStamped, queue_size=1)
        twist = rospy.Publisher("/car2/cmd_vel", Twist, queue_size=1)
        cmd = AckermannDriveStamped()
        cmd.drive.speed = 0.5
        start1, start2 = position(self.truth_now("car1")), position(self.truth_now("car2"))
        send(drive, cmd, "/car1/ackermann_cmd")
        self.sim.run(1.0, before_chunk=lambda: drive.publish(cmd))
        self.assertAlmostEqual(distance(position(self.truth_now("car1")), start1), 0.5, delta=0.1)
        self.assertLess(distance(position(self.truth_now("car2")), start2), 0.005)

        # Twist: angular.z is a yaw rate (measured by ground truth), and car1 ignores it.
        self.sim.run(1.0)  # car1 brakes after its command timeout
        t = Twist()
        t.linear.x = -0.4  # backwards: the same yaw rate needs the opposite steering angle
        t.angular.z = 0.5
        start1 = position(self.truth_now("car1"))
        send(twist, t, "/car2/cmd_vel")
        self.sim.run(2.0, before_chunk=lambda: twist.publish(t))
        self.assertAlmostEqual(self.truth_now("car2").twist.twist.angular.z, 0.5, delta=0.05 * 0.5)
        self.assertLess(distance(position(self.truth_now("car1")), start1), 0.01)  # stopped after its timeout
        self.sim.run(1.0)  # car2 brakes too (timeout)

    def test_command_timeout_brakes(self):
        drive = rospy.Publisher("/car1/ackermann_cmd", AckermannDriveStamped, queue_size=1)
        cmd = AckermannDriveStamped()
        cmd.drive.speed = -0.4
        start = position(self.truth_now("car1"))
        send(drive, cmd, "/car1/ackermann_cmd")  # once only
        self.sim.step(2000)
        moved = distance(position(self.truth_now("car1")), start)
        # Driven for the 0.5 s timeout (about 0.2 m), then braked: far less than 2 s x 0.4 m/s.
        self.assertGreater(moved, 0.1)
        self.assertLess(moved, 0.35)
        v = self.truth_now("car1").twist.twist.linear
        self.assertLess(math.hypot(v.x, v.y), 0.01)

    def test_odometry_tf_and_joint_states_are_namespaced(self):
        odoms = Latest("/car2/odom", Odometry)
        joints = Latest("/car2/joint_states", JointState)
        connected(joints.sub, "/car2/joint_states")
        buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(buffer)
        self.sim.step(200)
        wait_for(lambda: odoms.messages and joints.messages, "/car2/odom and /car2/joint_states")
        self.assertEqual(odoms.last.header.frame_id, "car2/odom")
        self.assertEqual(odoms.last.child_frame_id, "car2/base_footprint")
        self.assertEqual(set(joints.last.name), {
            "left_steering_joint", "right_steering_joint", "left_front_wheel_joint", "right_front_wheel_joint",
            "left_rear_wheel_joint", "right_rear_wheel_joint"})
        for car in ("car1", "car2"):
            # The listener may have connected to /tf after the steps above published odom -> base.
            self.sim.step_until(lambda: buffer.can_transform(f"{car}/odom", f"{car}/base_footprint", rospy.Time(0)),
                                f"TF {car}/odom -> {car}/base_footprint")
            wait_for(lambda: buffer.can_transform("world", f"{car}/odom", rospy.Time(0)), f"TF world -> {car}/odom")


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "ackermann_lidar", AckermannLidarTest)
