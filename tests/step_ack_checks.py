#!/usr/bin/env python3
"""Checks of acknowledged delivery (see step_ack.test): a Twist published just before a one-step
~step request takes effect in that step when the simulator acknowledged it (~wait_for_messages),
sent directly and through a relay that delivers it 2 s of wall time late; the same command through
the relay without the acknowledgement is not in effect after the step (the old way was late). The
planar move fixture's velocity is its last command after every step: the model's twist
(/gazebo/get_model_state) shows which command the step used."""
import time
import unittest

import rospy
import rostest
from gazebo_msgs.srv import GetModelState
from geometry_msgs.msg import Twist

from conde_common.delivery import AcknowledgedPublisher
from conde_msgs.srv import WaitForMessages
from stepped_sim import WALL_TIMEOUT_S, SteppedSim, connected, twist

RELAY_DELAY_S = 2.0  # step_ack.test's delayed_relay ~delay_s
SPEEDS_M_S = [0.3, 0.0, -0.2, 0.5, 0.0]  # each differs from the one before


class StepAckTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("step_ack_test")
        cls.sim = SteppedSim()
        rospy.wait_for_service("/gazebo/get_model_state", timeout=WALL_TIMEOUT_S)
        cls.get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        cls.wait_for_messages = rospy.ServiceProxy("/conde_sim/wait_for_messages", WaitForMessages)
        cls.sim.step(200)  # settle on the ground

    def velocity_m_s(self):
        state = self.get_state("planar", "")
        self.assertTrue(state.success, state.status_message)
        return state.twist.linear.x

    def relay_linked(self, slow):
        """Sends the current command (0, where test 1 ends) through the relay until the simulator
        has one from it (the relay's publisher may not be connected yet); returns the relay's count."""
        baseline = self.wait_for_messages("/planar/cmd_vel", "/delayed_relay", 0, 1.0).received
        for attempt in range(20):
            slow.publish(twist(0.0))
            if self.wait_for_messages("/planar/cmd_vel", "/delayed_relay", baseline + 1, 3 * RELAY_DELAY_S).success:
                if attempt > 0:  # an earlier attempt may still be under way: let it come, then count
                    time.sleep(3 * RELAY_DELAY_S)
                return self.wait_for_messages("/planar/cmd_vel", "/delayed_relay", 0, 1.0).received
        self.fail("the relay never delivered to the simulator")

    def test_1_an_acknowledged_command_takes_effect_in_the_next_step(self):
        pub = rospy.Publisher("/planar/cmd_vel", Twist, queue_size=1)
        connected(pub, "/planar/cmd_vel")
        cmd = AcknowledgedPublisher(pub)
        for _ in range(4):
            for vx in SPEEDS_M_S:
                cmd.send(twist(vx))
                self.sim.step(1)
                self.assertAlmostEqual(self.velocity_m_s(), vx, delta=1e-3)
        cmd.close()
        pub.unregister()

    def test_2_a_late_command_is_waited_for_and_unacknowledged_it_is_missed(self):
        slow = rospy.Publisher("/planar/cmd_vel_slow", Twist, queue_size=1)
        connected(slow, "/planar/cmd_vel_slow")
        received = self.relay_linked(slow)
        for vx in SPEEDS_M_S[:3]:
            before = self.velocity_m_s()
            # The old way: publish, step at once. The relay delivers a second later: the step ran
            # with the previous command.
            slow.publish(twist(vx))
            self.sim.step(1)
            self.assertAlmostEqual(self.velocity_m_s(), before, delta=1e-3, msg="the delayed command was not late")
            # Acknowledged: the simulator is asked for the relay's message before the step.
            received += 1
            ack = self.wait_for_messages("/planar/cmd_vel", "/delayed_relay", received, WALL_TIMEOUT_S)
            self.assertTrue(ack.success, ack.message)
            self.sim.step(1)
            self.assertAlmostEqual(self.velocity_m_s(), vx, delta=1e-3)

    def test_3_a_timeout_names_topic_and_node(self):
        response = self.wait_for_messages("/planar/cmd_vel", "/nobody", 1, 0.2)
        self.assertFalse(response.success)
        self.assertIn("/planar/cmd_vel", response.message)
        self.assertIn("/nobody", response.message)
        response = self.wait_for_messages("planar/cmd_vel", "", 0, 0.2)
        self.assertFalse(response.success)
        self.assertIn("resolved topic name", response.message)


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "step_ack", StepAckTest)
