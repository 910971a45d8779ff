#!/usr/bin/env python3
"""Wiring of the NAO (nao.test): nao.launch loads the 25 position controllers, nao_pose commands
the standing pose, the joints reach it, the IMU says the torso is upright, and a command to the
HipYawPitch controller moves both hips (mimic_joints). The simulation is stepped."""
import os

import rospy
import rostest
from std_msgs.msg import Float64

from conde_common.delivery import AcknowledgedPublisher
from conde_humanoid.poses import load_pose_commands
from nao_stepped import CONFIG_DIR, SteppedNaoTest
from stepped_sim import Latest, connected, send, wait_for


def stand_pose():
    """{joint: angle [rad]} of the stand pose, every joint (0 where the pose names none)."""
    commands = load_pose_commands(os.path.join(CONFIG_DIR, 'nao_poses.yaml'), 'stand',
                                  os.path.join(CONFIG_DIR, 'nao_controllers.yaml'))
    pose = {name.replace('_position_controller', ''): angle for name, angle in commands.items()}
    pose['LHipYawPitch'] = pose['RHipYawPitch'] = pose.pop('HipYawPitch')
    return pose


class NaoTest(SteppedNaoTest):
    NODE_NAME = 'nao_checks'

    def test_1_stands_in_the_commanded_pose(self):
        # nao_pose publishes the pose once, latched: every controller's command must come out of it.
        commands = load_pose_commands(os.path.join(CONFIG_DIR, 'nao_poses.yaml'), 'stand',
                                      os.path.join(CONFIG_DIR, 'nao_controllers.yaml'))
        received = {name: Latest('/%s/command' % name, Float64) for name in commands}
        for name, latest in received.items():
            wait_for(lambda: latest.messages, 'the stand pose from nao_pose on /%s/command' % name)
            self.assertEqual(latest.last.data, commands[name], name)
            latest.sub.unregister()  # the connections counted below are then the simulator's
        # The simulator may connect to some of them later than this test did: send the same pose
        # once more through connections known to be up, so that stepping starts from it.
        # Each acknowledged by the simulator (a new publisher: nothing of this node's is in flight).
        for name, angle in commands.items():
            pub = rospy.Publisher('/%s/command' % name, Float64, queue_size=1, latch=True)
            connected(pub, '/%s/command' % name)
            acknowledged = AcknowledgedPublisher(pub)
            acknowledged.send(Float64(angle))
            acknowledged.close()
        self.sim.run(3.0)
        position = self.positions()
        self.assertEqual(len(position), 26)
        for joint, angle in stand_pose().items():
            self.assertAlmostEqual(position[joint], angle, delta=0.02, msg=joint)
        q = self.imu.wait_until_stamped(self.sim.time_s, 0.01).orientation
        up_z = 1 - 2 * (q.x * q.x + q.y * q.y)  # torso z axis, world z component
        self.assertGreater(up_z, 0.98)

    def test_2_hip_yaw_pitch_drives_both_hips(self):
        pub = rospy.Publisher('/HipYawPitch_position_controller/command', Float64, queue_size=1)
        command = Float64(-0.2)
        send(pub, command, '/HipYawPitch_position_controller/command')
        # Sent again before each 50 ms (as a driver node would): one late message would only delay it.
        self.sim.run(1.0, before_chunk=lambda: pub.publish(command))
        position = self.positions()
        self.assertAlmostEqual(position['LHipYawPitch'], -0.2, delta=0.02)
        self.assertAlmostEqual(position['RHipYawPitch'], -0.2, delta=0.02)


if __name__ == '__main__':
    rostest.rosrun('conde_tests', 'nao', NaoTest)
