#!/usr/bin/env python3
"""Wiring test of sim.launch with an SDF world (see sdf_world.test)."""
import unittest

import rospy
import rostest
from gazebo_msgs.srv import GetModelState
from visualization_msgs.msg import Marker, MarkerArray

from stepped_sim import WALL_TIMEOUT_S, SteppedSim, wait_for


class SdfWorldTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("sdf_world_test")
        cls.sim = SteppedSim()

    def test_world_markers_hold_the_meshes(self):
        arrays = []
        sub = rospy.Subscriber("/conde_sim/world_markers", MarkerArray, arrays.append)
        wait_for(lambda: arrays, "/conde_sim/world_markers (latched)")
        sub.unregister()
        meshes = [m for m in arrays[-1].markers if m.type == Marker.TRIANGLE_LIST]
        # The STL block's visual, the Collada block's visual, the dynamic mesh block: 12 triangles each.
        self.assertEqual(len(meshes), 3)
        self.assertTrue(all(len(m.points) == 36 for m in meshes))

    def test_dynamic_models_fall_onto_the_ground(self):
        rospy.wait_for_service("/gazebo/get_model_state", timeout=WALL_TIMEOUT_S)
        get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        self.assertAlmostEqual(get_state("falling_box__link", "world").pose.position.z, 1.0, delta=0.05)
        self.sim.step(1000)  # 2 s at shapes.world's 2 ms step
        self.assertAlmostEqual(self.sim.time_s, 2.0, delta=0.01)
        for name, resting_z in (("falling_box__link", 0.1), ("falling_ball__link", 0.1), ("falling_block__link", 0.0)):
            state = get_state(name, "world")
            self.assertTrue(state.success, state.status_message)
            self.assertAlmostEqual(state.pose.position.z, resting_z, delta=0.01, msg=name)


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "sdf_world", SdfWorldTest)
