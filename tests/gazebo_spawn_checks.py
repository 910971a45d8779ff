#!/usr/bin/env python3
"""Checks of gazebo_spawn.test: a course lab's Gazebo calls against conde_sim. Conde, spawned by
spawn_model, shows up in /gazebo/model_states at its spawn pose; set_model_state moves it
(service and topic), get_model_state and get_link_state see the new pose; a body wrench pushes
it; delete_model removes it."""
import math
import unittest

import rospy
import rostest
from gazebo_msgs.msg import ModelState, ModelStates
from gazebo_msgs.srv import (ApplyBodyWrench, DeleteModel, GetLinkState, GetModelState, GetWorldProperties,
                             SetModelState)
from geometry_msgs.msg import Point, Wrench
from nav_msgs.msg import Odometry

from stepped_sim import WALL_TIMEOUT_S, Latest, SteppedSim, connected, wait_for


def yaw_of(q):
    return math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z))


def model_state(name, x, y, yaw):
    state = ModelState(model_name=name, reference_frame="world")
    state.pose.position.x, state.pose.position.y = x, y
    state.pose.orientation.z, state.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    return state


class GazeboSpawnTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("gazebo_spawn_test")
        for name in ("get_world_properties", "get_model_state", "set_model_state", "delete_model"):
            rospy.wait_for_service("/gazebo/" + name, timeout=WALL_TIMEOUT_S)
        cls.world = rospy.ServiceProxy("/gazebo/get_world_properties", GetWorldProperties)
        cls.get_state = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)
        cls.set_state = rospy.ServiceProxy("/gazebo/set_model_state", SetModelState)
        cls.sim = SteppedSim("/gazebo")
        wait_for(lambda: "conde" in cls.world().model_names, "spawn_model to add conde")

    def assert_pose(self, pose, x, y, yaw, tol_m=0.01):
        self.assertAlmostEqual(pose.position.x, x, delta=tol_m)
        self.assertAlmostEqual(pose.position.y, y, delta=tol_m)
        self.assertAlmostEqual(yaw_of(pose.orientation), yaw, delta=0.02)

    def latest_conde(self, states):
        def seen():
            return states.messages and "conde" in states.messages[-1].name
        self.sim.step_until(seen, "conde in /gazebo/model_states")
        message = states.messages[-1]
        return message.pose[message.name.index("conde")]

    def test_1_spawned_at_its_pose_in_model_states(self):
        states = Latest("/gazebo/model_states", ModelStates)
        connected(states.sub, "/gazebo/model_states")
        self.sim.step(100)
        self.assert_pose(self.latest_conde(states), 0.5, -0.2, 0.3)

    def test_1_spawned_robot_runs_its_plugins(self):
        odom = Latest("/odom", Odometry)  # the diff drive plugin, loaded when spawned
        connected(odom.sub, "/odom")
        self.sim.step_until(lambda: odom.messages, "/odom from the spawned robot's diff drive")
        self.assertEqual(odom.messages[-1].child_frame_id, "base_footprint")

    def test_2_set_model_state_moves_it(self):
        answer = self.set_state(model_state("conde", 1.5, 1.0, 1.0))
        self.assertTrue(answer.success, answer.status_message)
        self.assertEqual(answer.status_message, "SetModelState: set model state done")
        self.sim.step(20)
        got = self.get_state("conde", "world")
        self.assertTrue(got.success, got.status_message)
        self.assert_pose(got.pose, 1.5, 1.0, 1.0)
        wheel = rospy.ServiceProxy("/gazebo/get_link_state", GetLinkState)("conde::left_wheel", "conde")
        self.assertTrue(wheel.success, wheel.status_message)
        self.assertAlmostEqual(wheel.link_state.pose.position.y, 0.165, delta=0.03)  # left of the base
        states = Latest("/gazebo/model_states", ModelStates)
        connected(states.sub, "/gazebo/model_states")
        self.assert_pose(self.latest_conde(states), 1.5, 1.0, 1.0)

    def test_3_set_model_state_topic_moves_it(self):
        pub = rospy.Publisher("/gazebo/set_model_state", ModelState, queue_size=1)
        connected(pub, "/gazebo/set_model_state")
        target = model_state("conde", -1.0, 0.5, -0.5)

        def arrived():
            pub.publish(target)
            return abs(self.get_state("conde", "").pose.position.x + 1.0) < 0.01

        self.sim.step_until(arrived, "the set_model_state topic to move conde")
        self.sim.step(20)
        self.assert_pose(self.get_state("conde", "").pose, -1.0, 0.5, -0.5)

    def test_4_body_wrench_pushes_it(self):
        start = self.get_state("conde", "").pose.position
        push = rospy.ServiceProxy("/gazebo/apply_body_wrench", ApplyBodyWrench)
        wrench = Wrench()
        wrench.force.z = 200.0  # lifts it off the ground for 0.1 s
        answer = push("conde::base_footprint", "world", Point(), wrench, rospy.Time(), rospy.Duration(0.1))
        self.assertTrue(answer.success, answer.status_message)
        self.sim.step(100)
        self.assertGreater(self.get_state("conde", "").pose.position.z, start.z + 0.05)

    def test_5_delete_model_removes_it(self):
        answer = rospy.ServiceProxy("/gazebo/delete_model", DeleteModel)("conde")
        self.assertTrue(answer.success, answer.status_message)
        self.assertEqual(self.world().model_names, [])
        got = self.get_state("conde", "")
        self.assertFalse(got.success)
        self.assertEqual(got.status_message, "GetModelState: model [conde] does not exist")
        self.sim.step(100)  # the world steps on without it


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "gazebo_spawn", GazeboSpawnTest)
