"""Analytic leg IK of the NAO (conde_humanoid/leg_ik.py): round trips through its forward
kinematics, and that forward kinematics against the chain of the URDF (nao.urdf.xacro) itself."""

import itertools
import os
import xml.etree.ElementTree as ET

import numpy as np
import pytest
import rospkg

from conde_humanoid import leg_ik
from conde_testing.ros_harness import xacro_finding

TARGETS = [np.array([x, y, z]) for x, y, z in itertools.product((-0.04, 0.0, 0.05), (0.0, 0.03), (-0.19, -0.15))]


@pytest.mark.parametrize('side', ['L', 'R'])
@pytest.mark.parametrize('yaw', [0.0, 0.2, -0.2])
def test_round_trip_reaches_the_ankle_target_with_a_flat_yawed_sole(side, yaw):
    for offset in TARGETS:
        target = leg_ik.hip_position(side) + np.array([offset[0], leg_ik.side_sign(side) * offset[1], offset[2]])
        q = leg_ik.inverse(side, target, yaw)
        ankle, rotation = leg_ik.forward(side, q)
        np.testing.assert_allclose(ankle, target, atol=1e-12)
        np.testing.assert_allclose(rotation, leg_ik.rot_z(yaw), atol=1e-9)


def test_joint_angles_come_back_for_a_flat_foot():
    q = (0.0, 0.1, -0.5, 0.9, -0.4, -0.1)  # roll and pitch sums 0: the sole is flat
    ankle, _ = leg_ik.forward('L', q)
    np.testing.assert_allclose(leg_ik.inverse('L', ankle), q, atol=1e-12)


def test_symmetric_yaw_gives_one_hip_yaw_pitch_for_both_legs():
    left = np.array([0.0, 0.05, -0.25])
    right = np.array([0.0, -0.05, -0.25])
    assert leg_ik.solve_hip_yaw_pitch('L', left, 0.2) == pytest.approx(leg_ik.solve_hip_yaw_pitch('R', right, -0.2))
    angles = leg_ik.inverse_pair(left, 0.2, right, -0.2)
    assert angles['LHipYawPitch'] == angles['RHipYawPitch'] < 0


def test_out_of_reach_is_an_error_naming_the_leg():
    with pytest.raises(leg_ik.IkError, match="out of the L leg's reach"):
        leg_ik.inverse('L', np.array([0.0, 0.05, -0.4]))


def _urdf():
    xacro = xacro_finding(rospkg.RosPack().get_path('conde_description'))
    path = os.path.join(rospkg.RosPack().get_path('conde_description'), 'robots', 'nao.urdf.xacro')
    return ET.fromstring(xacro.process_file(path, mappings={}).toxml())


def _origin(joint):
    origin = joint.find('origin')
    xyz = [float(v) for v in origin.get('xyz', '0 0 0').split()]
    rpy = [float(v) for v in origin.get('rpy', '0 0 0').split()]
    rotation = leg_ik.rot_z(rpy[2]) @ leg_ik.rot_y(rpy[1]) @ leg_ik.rot_x(rpy[0])
    return np.array(xyz), rotation


@pytest.mark.parametrize('side', ['L', 'R'])
def test_forward_kinematics_matches_the_urdf_chain(side):
    robot = _urdf()
    by_child = {j.find('child').get('link'): j for j in robot.findall('joint')}
    chain, link = [], '%s_sole' % side.lower()
    while link != 'torso':
        joint = by_child[link]
        chain.insert(0, joint)
        link = joint.find('parent').get('link')
    rng = np.random.default_rng(7)
    for _ in range(20):
        q = rng.uniform(-0.4, 0.4, 6)
        angles = dict(zip((side + n for n in leg_ik.LEG_JOINTS), q))
        position, rotation = np.zeros(3), np.eye(3)
        for joint in chain:
            xyz, r = _origin(joint)
            position = position + rotation @ xyz
            rotation = rotation @ r
            if joint.get('type') != 'fixed':
                axis = np.array([float(v) for v in joint.find('axis').get('xyz').split()])
                rotation = rotation @ leg_ik.rot_axis(axis / np.linalg.norm(axis), angles[joint.get('name')])
        ankle, foot = leg_ik.forward(side, q)
        np.testing.assert_allclose(position, ankle + foot @ np.array([0, 0, -leg_ik.FOOT_HEIGHT_M]), atol=1e-5)
        np.testing.assert_allclose(rotation, foot, atol=1e-5)
