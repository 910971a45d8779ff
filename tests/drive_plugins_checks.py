#!/usr/bin/env python3
"""Checks of the drive and force plugins (see drive_plugins.test): skid steer drives a commanded
distance and turns, planar move follows cmd_vel, force accelerates a known mass at F/m and f3d
reports the applied force. The simulation is stepped (1 ms steps)."""
import math
import time
import unittest

import rospy
import rostest
from gazebo_msgs.srv import ApplyBodyWrench, BodyRequest, GetModelState, GetPhysicsProperties
from geometry_msgs.msg import Point, Twist, Wrench, WrenchStamped
from nav_msgs.msg import Odometry

from stepped_sim import Latest, SteppedSim, connected, twist

BOX_MASS_KG = 2.0  # tests/fixtures/force_box.urdf


def yaw_of(q):
    return math.atan2(2.0 * (q.w * q.z + q.x * q.y), 1.0 - 2.0 * (q.y * q.y + q.z * q.z))


class DrivePluginsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("drive_plugins_test")
        cls.sim = SteppedSim()
        rospy.wait_for_service("/gazebo/get_model_state", timeout=60)
        cls.get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        cls.physics = rospy.ServiceProxy("/gazebo/get_physics_properties", GetPhysicsProperties)
        cls.apply_wrench = rospy.ServiceProxy("/gazebo/apply_body_wrench", ApplyBodyWrench)
        cls.clear_wrenches = rospy.ServiceProxy("/gazebo/clear_body_wrenches", BodyRequest)

    def pose(self, model):
        state = self.get_state(model, "")
        self.assertTrue(state.success, state.status_message)
        return state.pose

    def drive(self, topic, command, seconds):
        """Sends `command` on `topic` every 50 ms of simulated time for `seconds`."""
        pub = rospy.Publisher(topic, Twist, queue_size=1)
        connected(pub, topic)
        self.sim.run(seconds, before_chunk=lambda: pub.publish(command))
        pub.publish(twist())
        time.sleep(0.2)
        pub.unregister()

    def test_skid_steer_drives_and_turns(self):
        odom = Latest.connected("/skid/odom", Odometry)
        self.sim.step(500)  # settle on the wheels
        start = self.pose("skid")
        self.drive("/skid/cmd_vel", twist(x_m_s=0.4), 2.0)
        end = self.pose("skid")
        travelled = math.hypot(end.position.x - start.position.x, end.position.y - start.position.y)
        rospy.loginfo("skid steer: travelled %.4f m of 0.8", travelled)
        self.assertAlmostEqual(travelled, 0.8, delta=0.08, msg="0.4 m/s for 2 s")
        self.assertLess(abs(yaw_of(end.orientation) - yaw_of(start.orientation)), 0.05, "straight ahead")
        last = odom.wait_until_stamped(self.sim.time_s - 0.2, 0.01)  # before the stop command arrived
        self.assertEqual((last.header.frame_id, last.child_frame_id), ("odom", "base_footprint"))
        self.assertEqual([last.pose.covariance[i] for i in (0, 7, 35)], [0.0002, 0.0003, 0.02])
        self.sim.step(500)
        start_yaw = yaw_of(self.pose("skid").orientation)
        self.drive("/skid/cmd_vel", twist(yaw_rate_rad_s=0.8), 2.0)
        turned = math.remainder(yaw_of(self.pose("skid").orientation) - start_yaw, 2 * math.pi)
        rospy.loginfo("skid steer: turned %.4f rad of 1.6", turned)
        # Skid steering slips sideways in a turn: the turn falls short of 1.6 rad, but not by much.
        self.assertGreater(turned, 0.6 * 1.6, f"turned {turned:.3f} rad of 1.6")
        self.assertLess(turned, 1.1 * 1.6, f"turned {turned:.3f} rad of 1.6")

    def test_planar_move_follows_cmd_vel(self):
        odom = Latest.connected("/planar/odom", Odometry)
        start = self.pose("planar")
        vx, vy, rate = 0.5, 0.2, 0.5
        t0 = self.sim.time_s
        self.drive("/planar/cmd_vel", twist(vx, vy, rate), 2.0)
        end = self.pose("planar")
        # Constant body-frame velocity while turning at `rate`: the integral of R(rate t) v dt.
        dx = (vx * math.sin(rate * 2.0) + vy * (math.cos(rate * 2.0) - 1.0)) / rate
        dy = (vx * (1.0 - math.cos(rate * 2.0)) + vy * math.sin(rate * 2.0)) / rate
        rospy.loginfo("planar move: moved (%.4f, %.4f) m, expected (%.4f, %.4f)", end.position.x - start.position.x,
                      end.position.y - start.position.y, dx, dy)
        self.assertAlmostEqual(end.position.x - start.position.x, dx, delta=0.03)
        self.assertAlmostEqual(end.position.y - start.position.y, dy, delta=0.03)
        self.assertAlmostEqual(yaw_of(end.orientation) - yaw_of(start.orientation), 1.0, delta=0.03)
        self.assertLess(abs(end.position.z - start.position.z), 0.01, "stays on the ground")
        odom.wait_until_stamped(t0 + 2.0, 0.05)  # the last of the counted messages may still be on its way
        stamps = [m.header.stamp.to_sec() for m in odom.messages if t0 < m.header.stamp.to_sec() <= t0 + 2.0]
        self.assertAlmostEqual(len(stamps), 40, delta=2, msg="odometryRate 20 Hz")
        last = odom.messages[-1]
        self.assertEqual((last.header.frame_id, last.child_frame_id), ("odom", "base_footprint"))

    def test_force_accelerates_mass_and_f3d_reports_it(self):
        g = -self.physics().gravity.z
        feedback = Latest.connected("/pushed/force_feedback", WrenchStamped)
        pub = rospy.Publisher("/pushed/force", Wrench, queue_size=1)
        connected(pub, "/pushed/force")
        start = self.pose("pushed")
        start_s = self.sim.time_s
        push = Wrench()
        push.force.x = 3.0                      # a_x = 1.5 m/s^2
        push.force.z = 2.0 * BOX_MASS_KG * g    # a_z = +g: lifts off the ground at once
        pub.publish(push)
        # One step at a time until f3d reports the push (the force plugin has it), then the rest of
        # the 0.5 s: a push that arrives late would otherwise shorten the run it is measured over.
        t = self.sim.step(1)
        while abs(feedback.wait_until_stamped(t, 0.0).wrench.force.x - push.force.x) > 1e-6:
            self.assertLess(t - start_s, 5.0, "the force plugin never applied the push")
            t = self.sim.step(1)
        t = self.sim.step(499)  # 500 steps pushed in all
        end = self.pose("pushed")
        moved_x, moved_z = end.position.x - start.position.x, end.position.z - start.position.z
        expected_x, expected_z = 0.5 * 1.5 * 0.5**2, 0.5 * g * 0.5**2  # x = a t^2 / 2
        rospy.loginfo("force: moved x %.5f m (expected %.5f), z %.5f m (expected %.5f)", moved_x, expected_x, moved_z,
                      expected_z)
        self.assertAlmostEqual(moved_x, expected_x, delta=0.005)
        self.assertAlmostEqual(moved_z, expected_z, delta=0.01)
        wrench = feedback.wait_until_stamped(t, 0.0).wrench
        self.assertEqual(feedback.last.header.frame_id, "world")
        self.assertAlmostEqual(wrench.force.x, push.force.x, places=6)
        self.assertAlmostEqual(wrench.force.z, push.force.z, places=6)
        self.assertAlmostEqual(math.hypot(wrench.torque.x, wrench.torque.y, wrench.torque.z), 0.0, places=6,
                               msg="applied at the centre of mass")
        pub.publish(Wrench())
        time.sleep(0.3)
        # A wrench of /gazebo/apply_body_wrench 0.1 m above the centre of mass: f3d reports the
        # force and its moment about the centre of mass (r x F).
        link = self.pose("pushed").position  # the centre of mass is 0.1 m above the link frame
        side = Wrench()
        side.force.y = 4.0
        reply = self.apply_wrench(body_name="pushed::base_link", reference_frame="world",
                                  reference_point=Point(link.x, link.y, link.z + 0.2), wrench=side,
                                  duration=rospy.Duration(-1))
        self.assertTrue(reply.success, reply.status_message)
        t = self.sim.step(1)
        wrench = feedback.wait_until_stamped(t, 0.0).wrench
        self.clear_wrenches("pushed::base_link")
        self.assertAlmostEqual(wrench.force.y, 4.0, places=6)
        self.assertAlmostEqual(wrench.torque.x, -0.1 * 4.0, delta=1e-3, msg="r = 0.1 m up, F along y")


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "drive_plugins", DrivePluginsTest)
