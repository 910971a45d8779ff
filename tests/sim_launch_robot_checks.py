#!/usr/bin/env python3
"""sim.launch with a robot from outside conde_description (see sim_launch_robot.test): the robot
~model is in the world, at the spawn pose, and stays there while the simulation steps."""
import unittest

import rospy
import rostest
from gazebo_msgs.srv import GetModelState, GetWorldProperties

from stepped_sim import SteppedSim


class SimLaunchRobotTest(unittest.TestCase):
    def test_robot_is_simulated(self):
        rospy.init_node("sim_launch_robot_test")
        model = rospy.get_param("~model")
        sim = SteppedSim()
        rospy.wait_for_service("/gazebo/get_world_properties", timeout=60)
        names = rospy.ServiceProxy("/gazebo/get_world_properties", GetWorldProperties)().model_names
        self.assertIn(model, names)
        sim.step(200)
        state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)(model, "")
        self.assertTrue(state.success, state.status_message)
        self.assertAlmostEqual(state.pose.position.x, 0.0, delta=0.01)
        self.assertAlmostEqual(state.pose.position.y, 0.0, delta=0.01)
        self.assertLess(abs(state.pose.position.z), 0.2, "resting on the ground at the spawn pose")


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "sim_launch_robot", SimLaunchRobotTest)
