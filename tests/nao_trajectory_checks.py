#!/usr/bin/env python3
"""The NAO's JointTrajectoryController (nao_trajectory.test): a two-point trajectory (the zero
posture at 0 s, the standing pose at 1 s, no velocities: linear) is followed: half-way at 0.5 s,
at the pose after 1 s, RHipYawPitch following LHipYawPitch, and the torso upright after 3 s. The
simulation is stepped."""
import os

import rospy
import rostest
import yaml
from trajectory_msgs.msg import JointTrajectory, JointTrajectoryPoint

from nao_stepped import CONFIG_DIR, SteppedNaoTest
from stepped_sim import send


def controller_config():
    with open(os.path.join(CONFIG_DIR, 'nao_trajectory_controller.yaml')) as f:
        return yaml.safe_load(f)['nao_trajectory_controller']


def stand_pose():
    with open(os.path.join(CONFIG_DIR, 'nao_poses.yaml')) as f:
        return yaml.safe_load(f)['stand']


class NaoTrajectoryTest(SteppedNaoTest):
    NODE_NAME = 'nao_trajectory_checks'

    def test_follows_a_trajectory_to_the_standing_pose(self):
        joints = controller_config()['joints']
        target = {j: stand_pose().get(j, 0.0) for j in joints}
        target['LHipYawPitch'] = -0.1  # to see RHipYawPitch follow it
        msg = JointTrajectory(joint_names=list(reversed(joints)))  # any order
        msg.points = [JointTrajectoryPoint(positions=[0.0] * len(joints), time_from_start=rospy.Duration(0)),
                      JointTrajectoryPoint(positions=[target[j] for j in msg.joint_names],
                                           time_from_start=rospy.Duration(1.0))]
        # Stamped with the simulated time it starts at (the simulation stands until it is sent): a
        # message that arrives a few steps late is then sampled from that time, not started late.
        # One step first: a zero stamp would mean "on receipt".
        msg.header.stamp = rospy.Time.from_sec(self.sim.step(1))
        pub = rospy.Publisher('/nao_trajectory_controller/command', JointTrajectory, queue_size=1)
        send(pub, msg, '/nao_trajectory_controller/command')
        self.sim.run(0.5, every_s=0.5)
        half = self.positions()
        for joint in ('LKneePitch', 'RKneePitch', 'LShoulderPitch'):
            self.assertAlmostEqual(half[joint], target[joint] / 2, delta=0.03, msg=joint)
        self.sim.run(2.5)
        position = self.positions()
        for joint, angle in target.items():
            self.assertAlmostEqual(position[joint], angle, delta=0.02, msg=joint)
        self.assertAlmostEqual(position['RHipYawPitch'], -0.1, delta=0.02)
        q = self.imu.wait_until_stamped(self.sim.time_s, 0.01).orientation
        self.assertGreater(1 - 2 * (q.x * q.x + q.y * q.y), 0.98)  # torso upright


if __name__ == '__main__':
    rostest.rosrun('conde_tests', 'nao_trajectory', NaoTrajectoryTest)
