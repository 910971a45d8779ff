#!/usr/bin/env python3
"""Wiring of libgazebo_ros_control.so with a real roscore (ros_control.test): the six controllers
of the Major-Alvega-style YAML listen on <controller>/command, the joint_state_ctrlr publishes
/joint_states, and commanding them as the original ackermann_controller did steers and drives the
car. The simulation is stepped."""
import math
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState
from std_msgs.msg import Float64

from stepped_sim import Latest, SteppedSim, connected

# As the original ackermann_controller computes them for the test
# car (L = 0.33 m, half track d = 0.12 m, wheel radius r = 0.05 m): 0.5 m/s at 0.3 rad.
L_M, D_M, R_WHEEL_M, SPEED_MPS, DELTA_RAD = 0.33, 0.12, 0.05, 0.5, 0.3
TURN_M = L_M / math.tan(DELTA_RAD)
STEERING = {"left_steering_ctrlr": math.atan(L_M / (TURN_M - D_M)),     # [rad]
            "right_steering_ctrlr": math.atan(L_M / (TURN_M + D_M))}
WHEELS = {                                                               # [rad/s]
    "left_front_wheel_ctrlr": SPEED_MPS * math.hypot(TURN_M - D_M, L_M) / (TURN_M * R_WHEEL_M),
    "right_front_wheel_ctrlr": SPEED_MPS * math.hypot(TURN_M + D_M, L_M) / (TURN_M * R_WHEEL_M),
    "left_rear_wheel_ctrlr": SPEED_MPS * (TURN_M - D_M) / (TURN_M * R_WHEEL_M),
    "right_rear_wheel_ctrlr": SPEED_MPS * (TURN_M + D_M) / (TURN_M * R_WHEEL_M),
}
JOINT = {name: name.replace("_ctrlr", "_joint") for name in list(STEERING) + list(WHEELS)}


class RosControlTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("ros_control_checks")
        cls.sim = SteppedSim()

    def test_controllers_steer_and_drive_the_car(self):
        joints = Latest.connected("/joint_states", JointState)
        truth = Latest.connected("/ground_truth/odom", Odometry)
        publishers = {name: rospy.Publisher(f"/{name}/command", Float64, queue_size=1)
                      for name in list(STEERING) + list(WHEELS)}
        for name, pub in publishers.items():
            connected(pub, f"/{name}/command")

        def command():
            for name, angle in STEERING.items():
                publishers[name].publish(Float64(angle))
            for name, speed in WHEELS.items():
                publishers[name].publish(Float64(speed))

        self.sim.run(2.0, every_s=1.0 / 30, before_chunk=command)  # 30 Hz, as ackermann_controller
        state = joints.wait_until_stamped(self.sim.time_s, 1.0 / 30)
        position = dict(zip(state.name, state.position))
        velocity = dict(zip(state.name, state.velocity))
        effort = dict(zip(state.name, state.effort))
        for name, angle in STEERING.items():
            self.assertAlmostEqual(position[JOINT[name]], angle, delta=0.01, msg=name)
        for name, speed in WHEELS.items():
            self.assertAlmostEqual(velocity[JOINT[name]], speed, delta=0.05 * speed, msg=name)
        self.assertEqual(len(state.name), 6)  # every movable joint
        self.assertNotEqual(effort["left_rear_wheel_joint"], 0.0)  # the controller's output
        odom = truth.wait_until_stamped(self.sim.time_s, 0.02)
        v = odom.twist.twist.linear
        self.assertAlmostEqual(math.hypot(v.x, v.y), SPEED_MPS, delta=0.05 * SPEED_MPS)
        self.assertAlmostEqual(odom.twist.twist.angular.z, SPEED_MPS / TURN_M, delta=0.05 * SPEED_MPS / TURN_M)
        # Messages carry simulated time.
        self.assertAlmostEqual(state.header.stamp.to_sec(), self.sim.time_s, delta=1.0 / 30 + 1e-6)


if __name__ == "__main__":
    rostest.rosrun("conde_tests", "ros_control", RosControlTest)
