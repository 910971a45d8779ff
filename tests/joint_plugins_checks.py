#!/usr/bin/env python3
"""Checks of the tricycle drive, joint pose trajectory and force/torque sensor plugins (see
joint_plugins.test): the tricycle drives the arc its steering angle commands and its encoder
odometry follows it; the arm reaches the poses of a trajectory at their times; the hinge of a
hanging mass reports its weight. The simulation is stepped (1 ms steps)."""
import math
import time
import unittest

import rospy
import rostest
import tf2_ros
from gazebo_msgs.srv import GetPhysicsProperties
from geometry_msgs.msg import Twist, WrenchStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from stepped_sim import Latest, ModelPoses, SteppedSim, connected, send

WHEELBASE_M = 0.5  # tests/fixtures/tricycle_robot.urdf: steering axis to rear axle
PENDULUM_MASS_KG = 2.0  # tests/fixtures/ft_pendulum.urdf
PENDULUM_OFFSET_ALONG_AXIS_M = 0.1


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class JointPluginsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("joint_plugins_test")
        cls.sim = SteppedSim()
        cls.pose = staticmethod(ModelPoses())

    def test_tricycle_drives_commanded_arc(self):
        odom = Latest.connected("/tri/odom", Odometry)
        joints = Latest.connected("/tri/joint_states", JointState)
        tf_buffer = tf2_ros.Buffer()
        tf2_ros.TransformListener(tf_buffer)
        self.sim.step(500)  # settle on the wheels
        start = self.pose("tri")
        start_yaw = yaw_of(start.orientation)
        speed, angle, seconds = 0.3, 0.3, 3.0
        pub = rospy.Publisher("/tri/cmd_vel", Twist, queue_size=1)
        connected(pub, "/tri/cmd_vel")
        command = Twist()
        command.linear.x, command.angular.z = speed, angle  # angular.z is the steering angle
        t0 = self.sim.time_s
        self.sim.run(seconds, before_chunk=lambda: pub.publish(command))
        end = self.pose("tri")
        # The rear axle's middle turns about the point on the rear axle line at L / tan(angle),
        # at yaw rate v sin(angle) / L (v: the front wheel's speed).
        turned = math.remainder(yaw_of(end.orientation) - start_yaw, 2 * math.pi)
        expected_turn = speed * math.sin(angle) * seconds / WHEELBASE_M
        radius = WHEELBASE_M / math.tan(angle)
        forward = (end.position.x - start.position.x) * math.cos(start_yaw) + \
            (end.position.y - start.position.y) * math.sin(start_yaw)
        left = -(end.position.x - start.position.x) * math.sin(start_yaw) + \
            (end.position.y - start.position.y) * math.cos(start_yaw)
        rospy.loginfo("tricycle: turned %.4f rad (expected %.4f), moved %.4f m ahead, %.4f m left "
                      "(expected %.4f, %.4f)", turned, expected_turn, forward, left,
                      radius * math.sin(turned), radius * (1 - math.cos(turned)))
        self.assertAlmostEqual(turned, expected_turn, delta=0.1 * expected_turn)
        # On the arc of the commanded radius, wherever along it the robot got to.
        self.assertAlmostEqual(forward, radius * math.sin(turned), delta=0.03)
        self.assertAlmostEqual(left, radius * (1 - math.cos(turned)), delta=0.03)
        # Encoder odometry from the rear wheels: starts at 0 and turns the same way as the robot.
        last = odom.wait_until_stamped(t0 + seconds, 0.02)
        self.assertEqual((last.header.frame_id, last.child_frame_id), ("odom", "base_footprint"))
        rospy.loginfo("tricycle: encoder odometry yaw %.4f, x %.4f, y %.4f", yaw_of(last.pose.pose.orientation),
                      last.pose.pose.position.x, last.pose.pose.position.y)
        self.assertAlmostEqual(yaw_of(last.pose.pose.orientation), turned, delta=0.05)
        self.assertAlmostEqual(last.pose.pose.position.x, forward, delta=0.03)
        self.assertAlmostEqual(last.pose.pose.position.y, left, delta=0.03)
        state = joints.wait_until_stamped(t0 + seconds, 0.02)
        self.assertEqual(state.name, ["front_steering_joint", "front_wheel_joint", "left_wheel_joint",
                                      "right_wheel_joint"])
        self.assertAlmostEqual(state.position[0], angle, delta=0.01, msg="steering at the commanded angle")
        self.assertAlmostEqual(state.velocity[1], speed / 0.075, delta=0.1 * speed / 0.075)
        self.assertEqual(list(state.effort), [10.0] * 4, "wheelTorque, as Gazebo reports it")
        # TF of the wheels (publishWheelTF) and of the odometry; they arrive while time runs.
        # Gazebo names each wheel frame after its joint, under the parent link's body.
        for parent, child in (("base_footprint", "front_steering_joint"), ("steering_link", "front_wheel_joint"),
                              ("odom", "base_footprint")):
            self.sim.step_until(lambda: tf_buffer.can_transform(parent, child, rospy.Time(0)),
                                f"TF {parent} -> {child}")
        steering = tf_buffer.lookup_transform("base_footprint", "front_steering_joint", rospy.Time(0))
        self.assertAlmostEqual(steering.transform.translation.x, 0.5, delta=1e-3)
        self.assertAlmostEqual(steering.transform.translation.z, 0.075, delta=1e-3)
        self.assertAlmostEqual(2 * math.atan2(steering.transform.rotation.z, steering.transform.rotation.w), angle,
                               delta=0.01)
        # Commands stop: the wheel stops after <cmdTimeout> (1 s).
        self.sim.step(2000)
        stopped = self.pose("tri")
        self.sim.step(500)
        self.assertLess(math.hypot(self.pose("tri").position.x - stopped.position.x,
                                   self.pose("tri").position.y - stopped.position.y), 0.005, "stopped")

    def test_joint_pose_trajectory_reaches_poses(self):
        joints = Latest.connected("/arm/joint_states", JointState)
        pub = rospy.Publisher("/arm/set_joint_trajectory", JointTrajectory, queue_size=1)
        trajectory = JointTrajectory()
        trajectory.header.frame_id = "world"
        trajectory.joint_names = ["elbow_joint", "shoulder_joint"]
        poses = [(0.5, [0.6, -0.4]), (1.0, [-0.3, 1.2]), (1.5, [0.0, 0.5])]
        for t, positions in poses:
            trajectory.points.append(JointTrajectoryPoint(positions=positions,
                                                          time_from_start=rospy.Duration(t)))
        send(pub, trajectory, "/arm/set_joint_trajectory")
        t0 = self.sim.time_s

        def positions_at(t):
            self.sim.step(max(0, round((t0 + t - self.sim.time_s) * 1000)))
            state = joints.wait_until_stamped(self.sim.time_s, 0.01)
            by_name = dict(zip(state.name, state.position))
            return [by_name[n] for n in trajectory.joint_names]

        before = positions_at(0.45)
        self.assertLess(max(abs(q) for q in before), 0.01, f"still at 0 before the first point: {before}")
        for t, expected in poses:
            reached = positions_at(t + 0.3)  # 10 rad/s at most (URDF limit)
            rospy.loginfo("joint pose trajectory: at %.2f s %s (expected %s)", t + 0.3, reached, expected)
            for q, e in zip(reached, expected):
                self.assertAlmostEqual(q, e, delta=0.01)
        held = positions_at(3.0)
        for q, e in zip(held, poses[-1][1]):
            self.assertAlmostEqual(q, e, delta=0.01, msg="the last pose is held")
        # A trajectory naming a joint the arm lacks is refused (logged) and the pose stays.
        bad = JointTrajectory(joint_names=["wrist_joint"],
                              points=[JointTrajectoryPoint(positions=[1.0], time_from_start=rospy.Duration(0.1))])
        send(pub, bad, "/arm/set_joint_trajectory")
        for q, e in zip(positions_at(3.5), poses[-1][1]):
            self.assertAlmostEqual(q, e, delta=0.01)
        time.sleep(0.1)

    def test_ft_sensor_reads_hanging_weight(self):
        g = -rospy.ServiceProxy("/gazebo/get_physics_properties", GetPhysicsProperties)().gravity.z
        wrenches = Latest.connected("/ft/ft_sensor_topic", WrenchStamped)
        self.sim.step(300)  # the hinge settles (it starts at rest, in equilibrium about its axis)
        t0 = self.sim.time_s
        # 0.5 s in chunks of five messages, each received before the next chunk: the plugin's
        # publisher queue holds 10 (as gazebo_ros's), so one burst of 50 could drop some.
        t1 = self.sim.run_received(0.5, [(wrenches, 0.01)])
        recent = [m for m in wrenches.messages if t0 < m.header.stamp.to_sec() <= t1]
        self.assertAlmostEqual(len(recent), 50, delta=1, msg="updateRate 100 Hz over 0.5 s")
        self.assertEqual(recent[-1].header.frame_id, "pendulum_link")

        def mean(values):
            return sum(values) / len(values)

        # The mean over 0.5 s: ODE's iterative solver scatters each step's constraint force
        # (a few percent; Bullet's stays within 0.1 %).
        fz = [m.wrench.force.z for m in recent]
        ty = [m.wrench.torque.y for m in recent]
        f_xy = math.hypot(mean([m.wrench.force.x for m in recent]), mean([m.wrench.force.y for m in recent]))
        t_xz = math.hypot(mean([m.wrench.torque.x for m in recent]), mean([m.wrench.torque.z for m in recent]))
        weight = PENDULUM_MASS_KG * g
        moment = -PENDULUM_OFFSET_ALONG_AXIS_M * weight
        rospy.loginfo("ft_sensor: force z mean %.4f N (%.4f..%.4f), torque y mean %.4f N m (%.4f..%.4f); weight "
                      "%.4f N, expected torque y %.4f N m; |force xy| %.4f, |torque xz| %.4f", mean(fz), min(fz),
                      max(fz), mean(ty), min(ty), max(ty), weight, moment, f_xy, t_xz)
        self.assertAlmostEqual(mean(fz), weight, delta=0.02 * weight, msg="the hinge holds the weight up")
        self.assertLess(f_xy, 0.02 * weight)
        # The mass hangs 0.1 m along the hinge axis: the hinge also holds the moment m g 0.1 about y.
        self.assertAlmostEqual(mean(ty), moment, delta=0.05 * abs(moment))
        self.assertLess(t_xz, 0.05)


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "joint_plugins", JointPluginsTest)
