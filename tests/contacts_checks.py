#!/usr/bin/env python3
"""Checks of the bumper plugin and of /conde_sim/contacts (see contacts.test). The simulation is
stepped: 50 Hz updates at a 1 ms step are 20 steps apart."""
import unittest

import rospy
import rostest
from gazebo_msgs.msg import ContactsState, ModelState
from gazebo_msgs.srv import ApplyBodyWrench, BodyRequest, GetModelState, SetModelState
from geometry_msgs.msg import Wrench

from stepped_sim import Latest, SteppedSim

ROBOT_LINK = "bot::base_link"


def pairs(msg):
    return {(s.collision1_name, s.collision2_name) for s in msg.states}


class ContactsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("contacts_test")
        cls.sim = SteppedSim()
        cls.bumper = Latest.connected("/bot/bumper", ContactsState)
        cls.contacts = Latest.connected("/conde_sim/contacts", ContactsState)
        rospy.wait_for_service("/gazebo/set_model_state", timeout=60)
        cls.set_state = rospy.ServiceProxy("/gazebo/set_model_state", SetModelState)
        cls.get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        cls.push = rospy.ServiceProxy("/gazebo/apply_body_wrench", ApplyBodyWrench)
        cls.stop_push = rospy.ServiceProxy("/gazebo/clear_body_wrenches", BodyRequest)

    def place(self, x, vx):
        state = ModelState()
        state.model_name = "bot"
        state.pose.position.x = x
        state.pose.orientation.w = 1.0
        state.twist.linear.x = vx
        self.assertTrue(self.set_state(state).success)

    def latest_after(self, topic, time_s):
        return topic.wait_until_stamped(time_s, 0.02)

    def check_apart(self):
        self.stop_push("bot::base_link")
        self.place(0.0, 0.0)
        t = self.sim.step(500)
        bumper = self.latest_after(self.bumper, t)
        self.assertEqual(pairs(bumper), {(ROBOT_LINK, "ground_plane")}, "only the ground under the box")
        self.assertEqual(self.latest_after(self.contacts, t).states, [], "the ground is not reported")

    def test_1_apart_nothing(self):
        self.check_apart()

    def test_2_pushed_into_the_crate(self):
        self.place(0.5, 1.0)  # frictionless: slides 0.2 m to the crate's face at x = 0.9 in 0.2 s
        wrench = Wrench()
        wrench.force.x = 5.0  # and keeps pushing (as a drive would), so it stays against the crate
        self.assertTrue(self.push(body_name="bot::base_link", reference_frame="world", wrench=wrench,
                                  duration=rospy.Duration(-1)).success)
        t = self.sim.step(1000)
        bumper = self.latest_after(self.bumper, t)
        x = self.get_state("bot", "").pose.position.x
        self.assertIn((ROBOT_LINK, "crate"), pairs(bumper), f"box at x = {x:.4f} m (face at {x + 0.1:.4f})")
        crate = [s for s in bumper.states if s.collision2_name == "crate"][0]
        self.assertGreater(len(crate.contact_positions), 0)
        for p, n in zip(crate.contact_positions, crate.contact_normals):
            self.assertAlmostEqual(p.x, 0.9, delta=0.02)
            self.assertLess(n.x, -0.9, "the crate pushes the box back (-x)")
        contacts = self.latest_after(self.contacts, t)
        self.assertEqual(pairs(contacts), {(ROBOT_LINK, "crate")})
        self.assertEqual(contacts.header.frame_id, "world")

    def test_3_apart_again(self):
        self.check_apart()


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "contacts", ContactsTest)
