#!/usr/bin/env python3
"""Checks of gazebo_spawn_sdf.test: SDF models spawned while the simulation runs. The world that
includes model://sun and model://ground_plane loaded (the node serves /gazebo/); the crate
(spawn_model -sdf -file) and the ball (-sdf -param) are in /gazebo/model_states at their spawn
poses and fall onto the ground; a static model of the model path (spawn_model -database) is
something a model spawned above it lands on; bad requests get Gazebo's status messages; a spawned
model is deleted (gone from the world and from what collides) and its name can be spawned again."""
import os
import subprocess
import unittest

import rospy
import rostest
from gazebo_msgs.msg import ModelStates
from gazebo_msgs.srv import DeleteModel, GetModelState, GetWorldProperties, SpawnModel
from geometry_msgs.msg import Pose

from stepped_sim import WALL_TIMEOUT_S, Latest, SteppedSim, connected, wait_for

FIXTURES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "fixtures", "gazebo_sdf")
CUBE_SDF = """<?xml version="1.0"?>
<sdf version="1.6">
  <model name="cube">
    <link name="link">
      <inertial><mass>0.2</mass></inertial>
      <collision name="collision">
        <geometry><box><size>0.1 0.1 0.1</size></box></geometry>
      </collision>
    </link>
  </model>
</sdf>"""


def pose_at(x, y, z):
    pose = Pose()
    pose.position.x, pose.position.y, pose.position.z = x, y, z
    pose.orientation.w = 1.0
    return pose


class GazeboSpawnSdfTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("gazebo_spawn_sdf_test")
        for name in ("get_world_properties", "get_model_state", "spawn_sdf_model"):
            rospy.wait_for_service("/gazebo/" + name, timeout=WALL_TIMEOUT_S)
        cls.world = rospy.ServiceProxy("/gazebo/get_world_properties", GetWorldProperties)
        cls.get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        cls.spawn = rospy.ServiceProxy("/gazebo/spawn_sdf_model", SpawnModel)
        cls.sim = SteppedSim("/gazebo")
        wait_for(lambda: {"crate", "ball"} <= set(cls.world().model_names), "spawn_model to add crate and ball")

    def test_1_spawned_models_in_model_states_at_their_poses(self):
        states = Latest("/gazebo/model_states", ModelStates)
        connected(states.sub, "/gazebo/model_states")
        self.sim.step_until(lambda: states.messages and "crate" in states.messages[-1].name, "crate in model_states")
        message = states.messages[-1]
        crate, ball = message.pose[message.name.index("crate")], message.pose[message.name.index("ball")]
        self.assertLess(self.sim.time_s, 0.1)  # still in the air
        self.assertAlmostEqual(crate.position.z, 1.0, delta=0.05)
        self.assertAlmostEqual(crate.orientation.z, 0.2474, delta=0.001)  # -Y 0.5: sin(0.25)
        self.assertAlmostEqual(ball.position.x, 1.0, delta=1e-6)
        self.assertAlmostEqual(ball.position.z, 0.5, delta=0.05)

    def test_2_they_fall_and_rest_on_the_ground(self):
        self.sim.step(1500)  # 1.5 s: a fall from 1 m takes 0.45 s
        crate, ball = self.get_state("crate", "world"), self.get_state("ball", "world")
        self.assertTrue(crate.success and ball.success, crate.status_message + ball.status_message)
        self.assertAlmostEqual(crate.pose.position.z, 0.1, delta=0.01)  # half its 0.2 m edge
        self.assertAlmostEqual(ball.pose.position.z, 0.1, delta=0.01)  # its radius
        self.assertAlmostEqual(ball.pose.position.x, 1.0, delta=0.01)

    def test_3_static_model_of_the_model_path_holds_what_lands_on_it(self):
        out = subprocess.run(["rosrun", "gazebo_ros", "spawn_model", "-database", "pedestal", "-model", "pedestal",
                              "-x", "-1.0"], capture_output=True, text=True, timeout=WALL_TIMEOUT_S)
        self.assertEqual(out.returncode, 0, out.stdout + out.stderr)
        self.assertIn("SpawnModel: Successfully spawned entity", out.stdout + out.stderr)
        answer = self.spawn("cube_on_pedestal", CUBE_SDF, "", pose_at(-1.0, 0.0, 1.0), "")
        self.assertEqual((answer.success, answer.status_message), (True, "SpawnModel: Successfully spawned entity"))
        self.sim.step(1500)
        self.assertAlmostEqual(self.get_state("cube_on_pedestal", "").pose.position.z, 0.35, delta=0.01)  # 0.3 + 0.05

    def test_4_initial_pose_relative_to_a_reference_frame(self):
        answer = self.spawn("cube_on_ball", CUBE_SDF, "", pose_at(0.0, 0.5, 0.0), "ball")
        self.assertTrue(answer.success, answer.status_message)
        pose = self.get_state("cube_on_ball", "").pose.position
        ball = self.get_state("ball", "").pose.position
        self.assertAlmostEqual(pose.x, ball.x, delta=1e-6)
        self.assertAlmostEqual(pose.y, ball.y + 0.5, delta=1e-6)

    def test_5_bad_requests_get_gazebo_status_messages(self):
        def answer(name, xml, frame=""):
            response = self.spawn(name, xml, "", pose_at(0, 0, 2), frame)
            return response.success, response.status_message

        self.assertEqual(answer("crate", CUBE_SDF), (False, "SpawnModel: Failure - entity already exists."))
        # A static model is no model of model_states here, but its name is taken.
        self.assertEqual(answer("pedestal", CUBE_SDF), (False, "SpawnModel: Failure - entity already exists."))
        self.assertEqual(
            answer("broken", "<sdf version='1.6'>\n<model name='broken'>\n<link name='l'>\n</model></sdf>"),
            (False, "SpawnModel: Failure - spawn_sdf_model 'broken':3: XML error: Error=XML_ERROR_MISMATCHED_ELEMENT "
             "ErrorID=14 (0xe) Line number=3: XMLElement name=link"))
        ok, message = answer("nameless", "<sdf version='1.6'>\n<model>\n<link name='l'/>\n</model>\n</sdf>")
        self.assertFalse(ok)
        self.assertTrue(message.startswith("SpawnModel: Failure - spawn_sdf_model 'nameless'"), message)
        self.assertEqual(answer("lost", CUBE_SDF, frame="nowhere"),
                         (False, "SpawnModel: Failure - reference_frame [nowhere] does not exist"))
        self.assertNotIn("broken", self.world().model_names)
        self.sim.step(10)  # the world steps on

    def test_6_delete_a_spawned_model_and_spawn_its_name_again(self):
        delete = rospy.ServiceProxy("/gazebo/delete_model", DeleteModel)
        answer = delete("cube_on_pedestal")
        self.assertEqual((answer.success, answer.status_message), (True, "DeleteModel: successfully deleted model"))
        self.assertNotIn("cube_on_pedestal", self.world().model_names)
        self.assertFalse(self.get_state("cube_on_pedestal", "").success)
        answer = delete("cube_on_pedestal")
        self.assertEqual((answer.success, answer.status_message),
                         (False, "DeleteModel: model [cube_on_pedestal] does not exist"))
        # the crate is gone from the physics too: a cube dropped where it rests falls to the ground
        crate = self.get_state("crate", "world").pose.position
        self.assertTrue(delete("crate").success)
        answer = self.spawn("crate", CUBE_SDF, "", pose_at(crate.x, crate.y, 0.5), "")
        self.assertEqual((answer.success, answer.status_message), (True, "SpawnModel: Successfully spawned entity"))
        self.sim.step(1500)
        self.assertAlmostEqual(self.get_state("crate", "").pose.position.z, 0.05, delta=0.01)  # on the ground


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "gazebo_spawn_sdf", GazeboSpawnSdfTest)
