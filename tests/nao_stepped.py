"""What the NAO's stepped rostest checks share: the controllers' config folder and a test case that
starts the node, the stepped simulator and the /joint_states and /imu subscriptions."""
import os
import unittest

import rospkg
import rospy
from sensor_msgs.msg import Imu, JointState

from stepped_sim import Latest, SteppedSim

CONFIG_DIR = os.path.join(rospkg.RosPack().get_path('conde_humanoid'), 'config')


class SteppedNaoTest(unittest.TestCase):
    NODE_NAME = 'nao_checks'  # each check script names its node

    @classmethod
    def setUpClass(cls):
        rospy.init_node(cls.NODE_NAME)
        cls.sim = SteppedSim()
        cls.joints = Latest.connected('/joint_states', JointState)
        cls.imu = Latest.connected('/imu', Imu)

    def positions(self):
        """{joint: position [rad]} of a joint state stamped at the current simulated time."""
        state = self.joints.wait_until_stamped(self.sim.time_s, 0.02)
        return dict(zip(state.name, state.position))
