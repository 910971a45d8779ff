"""Checks of the NAO H25 V4-class humanoid (robots/nao.urdf.xacro).

Run from the repository root:  /usr/bin/python3 -m pytest urdf/test

25 degrees of freedom (26 revolute joints, RHipYawPitch mimicking LHipYawPitch), the mass of the
documented robot, and each solid's inertia: the manufacturer's "Masses - V4" table gives it about
the link origin (I_o, in the link frame); the URDF must hold it about the centre of mass, moved by
the parallel-axis theorem. The table below is the documentation's (mass [kg], centre of mass [m],
I_o as ixx ixy ixz iyy iyz izz [kg m^2]).
"""

import numpy as np
import pytest

from description_helpers import (XacroRobot, args_id, assert_no_leftover_xacro, check_urdf, floats, joints, links,
                                 mass, movable_joints, plugin_params)

ROBOT = XacroRobot('nao.urdf.xacro')
process = ROBOT.process
robot = ROBOT.robot

DOCUMENTED = {
    'torso': (1.04956, (-0.00413, 0, 0.04342),
              (0.00506234, 1.43116e-05, 0.000155191, 0.00488013, -2.70793e-05, 0.0016103)),
    'Neck': (0.06442, (-1e-05, 0, -0.02742), (7.4993e-05, 1.57e-09, -1.7664e-08, 7.6e-05, -5.295e-08, 5.53373e-06)),
    'Head': (0.60533, (-0.00112, 0, 0.05258),
             (0.0026313, 8.78814e-06, 4.09847e-05, 0.00249112, -2.99579e-05, 0.000985735)),
    'LShoulder': (0.07504, (-0.00165, -0.02663, 0.00014),
                  (8.42843e-05, -2.02802e-06, 2.338e-08, 1.41556e-05, -1.97199e-08, 8.64195e-05)),
    'LBicep': (0.15777, (0.02455, 0.00563, 0.0033),
               (9.38999e-05, -4.71445e-05, -2.69947e-05, 0.000371518, -2.45977e-06, 0.000341901)),
    'LElbow': (0.06483, (-0.02744, 0, -0.00014),
               (5.59715e-06, 4.21e-09, 4.31901e-08, 7.54332e-05, -1.84e-09, 7.64434e-05)),
    'LForeArm': (0.07761, (0.02556, 0.00281, 0.00076),
                 (2.53322e-05, -2.34271e-06, 7.45892e-08, 8.91322e-05, -2.65499e-08, 8.72873e-05)),
    'l_wrist': (0.18533, (0.03434, -0.00088, 0.00308),
                (7.05493e-05, 5.71599e-06, -2.24744e-05, 0.000356062, 3.17771e-06, 0.000351919)),
    'RShoulder': (0.07504, (-0.00165, 0.02663, 0.00014),
                  (8.42843e-05, 2.02802e-06, 2.338e-08, 1.41556e-05, 1.97199e-08, 8.64195e-05)),
    'RBicep': (0.15777, (0.02455, -0.00563, 0.0033),
               (0.00011012, 7.66913e-05, -2.6046e-05, 0.000367576, 1.20983e-05, 0.000354618)),
    'RElbow': (0.06483, (-0.02744, 0, -0.00014),
               (5.59715e-06, 4.21e-09, 4.31901e-08, 7.54332e-05, -1.84e-09, 7.64434e-05)),
    'RForeArm': (0.07761, (0.02556, -0.00281, 0.00076),
                 (2.53907e-05, 2.33243e-06, -6.0117e-07, 8.92204e-05, 2.69399e-08, 8.72484e-05)),
    'r_wrist': (0.18533, (0.03434, 0.00088, 0.00308),
                (7.05493e-05, 5.71598e-06, -2.24744e-05, 0.000356062, 3.17771e-06, 0.000351919)),
    'LPelvis': (0.06981, (-0.00781, -0.01114, 0.02661),
                (8.15023e-05, -4.99449e-06, 1.27482e-05, 0.000101326, 2.34547e-05, 6.26236e-05)),
    'LHip': (0.13053, (-0.01549, 0.00029, -0.00515),
             (2.75836e-05, -2.23302e-08, -4.08164e-06, 9.82706e-05, -4.19045e-09, 8.80998e-05)),
    'LThigh': (0.38968, (0.00138, 0.00221, -0.05373),
               (0.00163672, 9.24514e-07, 8.53067e-05, 0.00159107, 3.83616e-05, 0.000303743)),
    'LTibia': (0.29142, (0.00453, 0.00225, -0.04936),
               (0.00118208, 6.33622e-07, 3.64969e-05, 0.00112865, 3.94952e-05, 0.000193228)),
    'LAnklePitch': (0.13416, (0.00045, 0.00029, 0.00685),
                    (3.85098e-05, -2.634e-08, 3.86194e-06, 7.42653e-05, 1.83402e-08, 5.48654e-05)),
    'l_ankle': (0.16184, (0.02542, 0.0033, -0.03239),
                (0.000269442, -5.69572e-06, 0.000139379, 0.000644342, 1.87409e-05, 0.000525757)),
    'RPelvis': (0.06981, (-0.00781, 0.01114, 0.02661),
                (8.99719e-05, 5.00219e-06, 1.27353e-05, 0.000105526, -2.77008e-05, 6.68872e-05)),
    'RHip': (0.13053, (-0.01549, -0.00029, -0.00515),
             (2.75866e-05, -1.91898e-08, -4.10822e-06, 9.827e-05, 2.51044e-09, 8.81034e-05)),
    'RThigh': (0.38968, (0.00138, -0.00221, -0.05373),
               (0.00163748, -8.39544e-07, 8.58831e-05, 0.00159221, -3.91763e-05, 0.000303978)),
    'RTibia': (0.29142, (0.00453, -0.00225, -0.04936),
               (0.00118283, -8.96502e-07, 2.79969e-05, 0.00112828, -3.8476e-05, 0.000191453)),
    'RAnklePitch': (0.13416, (0.00045, -0.00029, 0.00685),
                    (3.85081e-05, 6.434e-08, 3.87466e-06, 7.43108e-05, -4.58016e-09, 5.49132e-05)),
    'r_ankle': (0.16184, (0.02542, -0.0033, -0.03239),
                (0.000269302, 5.87505e-06, 0.000139133, 0.000643473, -1.88492e-05, 0.000525035)),
}
DOCUMENTED_WHOLE_ROBOT_KG = 5.19535
GRIPPER_KG = 0.005  # each finger set (not in the table: see the xacro's header)

HEAD = ['HeadYaw', 'HeadPitch']
ARM = ['ShoulderPitch', 'ShoulderRoll', 'ElbowYaw', 'ElbowRoll', 'WristYaw', 'Hand']
LEG = ['HipYawPitch', 'HipRoll', 'HipPitch', 'KneePitch', 'AnklePitch', 'AnkleRoll']
JOINTS = set(HEAD + [s + j for s in 'LR' for j in ARM + LEG])

# Motor limits of the documentation: joint -> (effort [N m], velocity [rad/s]), one per motor type.
REAL_LIMITS = {'HeadYaw': (1.547, 8.26797), 'LShoulderPitch': (1.329, 8.26797), 'LWristYaw': (0.4075, 24.6229),
               'LHand': (0.292, 8.33), 'LHipYawPitch': (3.348, 4.16174), 'RKneePitch': (3.023, 6.40239)}
ARG_SETS = [{}, {'limits': 'paper'}, {'fixed': 'true'}, {'cameras': 'false', 'imu': 'false'}]


def inertia_matrix(element):
    a = {k: float(element.get(k)) for k in ('ixx', 'ixy', 'ixz', 'iyy', 'iyz', 'izz')}
    return np.array([[a['ixx'], a['ixy'], a['ixz']], [a['ixy'], a['iyy'], a['iyz']], [a['ixz'], a['iyz'], a['izz']]])


def moved_to_centre_of_mass(mass_kg, com, i_o):
    """Parallel-axis theorem (tensor form): I_c = I_o - m (|c|^2 E - c c^T)."""
    ixx, ixy, ixz, iyy, iyz, izz = i_o
    i_o = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    c = np.array(com)
    return i_o - mass_kg * (c.dot(c) * np.eye(3) - np.outer(c, c))


@pytest.mark.parametrize('args', ARG_SETS, ids=args_id)
def test_check_urdf_accepts_every_argument_combination(args, tmp_path):
    text = process(**args)
    assert_no_leftover_xacro(text)
    printed = check_urdf(text, tmp_path, 'nao.urdf')
    assert 'root Link: %s' % ('world' if args.get('fixed') == 'true' else 'base_footprint') in printed


@pytest.mark.parametrize('arg,value', [('limits', 'gazebo'), ('fixed', 'yes'), ('cameras', '1'), ('imu', 'no')])
def test_bad_argument_values_are_refused(arg, value):
    with pytest.raises(Exception, match='ERROR_arg_%s' % arg):
        process(**{arg: value})


def test_25_degrees_of_freedom_with_the_hip_yaw_pitch_joints_coupled():
    root = robot()
    assert movable_joints(root) == JOINTS
    assert all(j.get('type') == 'revolute' for n, j in joints(root).items() if n in JOINTS)
    mimics = {n: j.find('mimic') for n, j in joints(root).items() if j.find('mimic') is not None}
    assert list(mimics) == ['RHipYawPitch']
    assert mimics['RHipYawPitch'].get('joint') == 'LHipYawPitch'
    assert len(movable_joints(root)) - len(mimics) == 25


def test_total_mass_is_the_documented_robot_plus_the_finger_sets():
    root = robot()
    total = sum(mass(link) for link in links(root).values())
    assert total == pytest.approx(DOCUMENTED_WHOLE_ROBOT_KG + 2 * GRIPPER_KG, abs=1e-6)
    assert 5.2 <= total <= 5.3
    assert sum(m for m, _, _ in DOCUMENTED.values()) == pytest.approx(DOCUMENTED_WHOLE_ROBOT_KG, abs=1e-6)


@pytest.mark.parametrize('name', sorted(DOCUMENTED))
def test_inertia_is_the_documented_one_moved_to_the_centre_of_mass(name):
    mass_kg, com, i_o = DOCUMENTED[name]
    inertial = links(robot())[name].find('inertial')
    assert float(inertial.find('mass').get('value')) == pytest.approx(mass_kg, rel=1e-12)
    assert floats(inertial.find('origin').get('xyz')) == pytest.approx(np.array(com), abs=1e-12)
    assert floats(inertial.find('origin').get('rpy')) == pytest.approx(np.zeros(3))
    np.testing.assert_allclose(inertia_matrix(inertial.find('inertia')), moved_to_centre_of_mass(mass_kg, com, i_o),
                               rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize('name', sorted(DOCUMENTED) + ['l_gripper', 'r_gripper'])
def test_inertia_is_positive_definite_and_physical(name):
    i_c = inertia_matrix(links(robot())[name].find('inertial/inertia'))
    moments = np.linalg.eigvalsh(i_c)
    assert moments.min() > 0, moments
    # principal moments of a real body obey the triangle inequality
    assert moments[0] + moments[1] >= moments[2] * (1 - 1e-9), moments


def test_joint_limits_are_the_motors_by_default():
    root = robot()
    for name, (effort, velocity) in REAL_LIMITS.items():
        limit = joints(root)[name].find('limit')
        assert float(limit.get('effort')) == effort, name
        assert float(limit.get('velocity')) == velocity, name
    assert all(joints(root)[n].find('dynamics') is None for n in JOINTS)


def test_paper_limits_are_uniform():
    root = robot(limits='paper')
    for name in JOINTS:
        joint = joints(root)[name]
        assert float(joint.find('limit').get('effort')) == 100.0
        assert float(joint.find('limit').get('velocity')) == 5.0
        assert float(joint.find('dynamics').get('damping')) == 0.0
        assert float(joint.find('dynamics').get('friction')) == 25.0
    # the range of motion stays the robot's
    assert float(joints(root)['LKneePitch'].find('limit').get('upper')) == 2.11255


def test_leg_geometry_is_the_documented_one():
    root = robot()
    # base_footprint is on the ground under the torso when the legs are straight
    assert floats(joints(root)['base_footprint_joint'].find('origin').get('xyz')) == pytest.approx(
        [0, 0, 0.085 + 0.1 + 0.1029 + 0.04519])
    offsets = {n: floats(joints(root)[n].find('origin').get('xyz')) for n in JOINTS}
    assert offsets['LHipYawPitch'] == pytest.approx([0, 0.05, -0.085])
    assert offsets['RHipYawPitch'] == pytest.approx([0, -0.05, -0.085])
    assert offsets['LKneePitch'] == pytest.approx([0, 0, -0.1])
    assert offsets['LAnklePitch'] == pytest.approx([0, 0, -0.1029])
    assert floats(joints(root)['LLeg_effector_fixedjoint'].find('origin').get('xyz')) == pytest.approx(
        [0, 0, -0.04519])
    assert floats(joints(root)['LHipYawPitch'].find('axis').get('xyz')) == pytest.approx(
        [0, 2 ** -0.5, -(2 ** -0.5)], abs=1e-6)


@pytest.mark.parametrize('foot', ['l_ankle', 'r_ankle'])
def test_feet_are_boxes_of_the_real_sole(foot):
    link = links(robot())[foot]
    collisions = link.findall('collision')
    assert len(collisions) == 1
    box = collisions[0].find('geometry/box')
    assert floats(box.get('size'))[:2] == pytest.approx([0.16, 0.088])
    # the sole's underside is on the l_sole/r_sole frame, 0.04519 m below the ankle axis
    z = floats(collisions[0].find('origin').get('xyz'))[2]
    assert z - floats(box.get('size'))[2] / 2 == pytest.approx(-0.04519)


def test_collisions_are_primitives_and_no_meshes_are_used():
    assert not list(robot().iter('mesh'))
    for link in links(robot()).values():
        for geometry in link.findall('collision/geometry'):
            assert [c.tag for c in geometry] in (['box'], ['cylinder'], ['sphere'])


def test_imu_in_the_torso_and_two_head_cameras():
    root = robot()
    imu = plugin_params(root, 'libgazebo_ros_imu_sensor.so')
    assert imu['bodyName'] == 'ImuTorso_frame'
    assert joints(root)['ImuTorso_joint'].find('parent').get('link') == 'torso'
    cameras = [p for p in root.iter('plugin') if p.get('filename') == 'libgazebo_ros_camera.so']
    assert sorted(p.find('cameraName').text for p in cameras) == ['CameraBottom', 'CameraTop']
    for name in ('CameraTop', 'CameraBottom'):
        assert joints(root)[name + '_joint'].find('parent').get('link') == 'Head'
    assert not [p for p in robot(cameras='false', imu='false').iter('plugin')
                if p.get('filename') != 'libgazebo_ros_control.so']


@pytest.mark.parametrize('camera', ['CameraTop', 'CameraBottom'])
def test_cameras_are_outside_the_head(camera):
    """The renderer draws the robot's own visuals: a camera inside the head would see its inside."""
    root = robot()
    head = links(root)['Head'].find('visual')
    centre = floats(head.find('origin').get('xyz'))
    radius = float(head.find('geometry/sphere').get('radius'))
    position = floats(joints(root)[camera + '_joint'].find('origin').get('xyz'))
    assert np.linalg.norm(position - centre) > radius + 0.005
