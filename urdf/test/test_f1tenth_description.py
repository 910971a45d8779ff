"""Checks of the F1/10 racecar description (robots/f1tenth.urdf.xacro).

Run from the repository root:  /usr/bin/python3 -m pytest urdf/test

The xacro is processed with the xacro Python module (PyPI xacro 1.13, ROS 1 line); the URDF is
parsed with xml.etree and validated with check_urdf (liburdfdom-tools). The numbers checked are
the ones the issue asks for (0.33 m wheelbase class, 1081-beam 270 degree LiDAR at 40 Hz, IMU at
100 Hz, camera at 30 Hz) and the F1TENTH car's (0.4189 rad of steering, about 3.7 kg).
"""

import itertools
import math

import numpy as np
import pytest

from description_helpers import (XacroRobot, args_id, assert_frame_tree, assert_no_leftover_xacro, check_urdf, floats,
                                 joints, links, mass, movable_joints, plugin_params)

ROBOT = XacroRobot('f1tenth.urdf.xacro')
process = ROBOT.process
robot = ROBOT.robot

WHEELBASE_M = 0.33
TRACK_M = 0.25
WHEEL_RADIUS_M = 0.05
MAX_STEERING_RAD = 0.4189
SENSORS = ('lidar', 'imu', 'camera')
ARG_SETS = [{}, {'drive': '2wd'}, {'prefix': 'car7/'}, {'odometry_source': 'world'}] + [
    dict(zip(SENSORS, values)) for values in itertools.product(('true', 'false'), repeat=3)
    if 'false' in values]
MOVABLE = {'left_steering_joint', 'right_steering_joint', 'left_front_wheel_joint',
           'right_front_wheel_joint', 'left_rear_wheel_joint', 'right_rear_wheel_joint'}


def position_in_root(root, link_name, root_name='base_footprint'):
    """Position of a link's origin in the root link at zero joint angles (all joint origins of
    this robot have rpy 0 except the camera's, which no other link hangs from)."""
    parents = {j.find('child').get('link'): j for j in root.findall('joint')}
    xyz = np.zeros(3)
    name = link_name
    while name != root_name:
        joint = parents[name]
        xyz += floats(joint.find('origin').get('xyz'))
        name = joint.find('parent').get('link')
    return xyz


def sensor(root, sensor_type):
    found = root.findall("gazebo/sensor[@type='%s']" % sensor_type)
    return found[0] if found else None


# ----------------------------------------------------------------------------------------------
# validity and arguments
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize('args', ARG_SETS, ids=args_id)
def test_check_urdf_accepts_every_argument_combination(args, tmp_path):
    printed = check_urdf(process(**args), tmp_path, 'f1tenth.urdf')
    assert 'root Link: %sbase_footprint' % args.get('prefix', '') in printed


@pytest.mark.parametrize('name, value', [('drive', 'awd'), ('lidar', 'yes'), ('imu', '1'), ('camera', 'on'),
                                         ('odometry_source', 'gps')])
def test_invalid_arguments_are_rejected_naming_the_argument(name, value):
    with pytest.raises(Exception, match='ERROR_arg_%s_must_be' % name):
        process(**{name: value})


def test_generated_urdf_has_no_leftover_xacro():
    assert_no_leftover_xacro(process())


# ----------------------------------------------------------------------------------------------
# frames and geometry
# ----------------------------------------------------------------------------------------------
def test_frame_tree_and_movable_joints():
    root = robot()
    assert root.get('name') == 'f1tenth'
    assert links(root)['base_footprint'].find('inertial') is None, 'the root link must be massless'
    assert_frame_tree(root, 'base_footprint', dict(
        {link: 'base_link' for link in ('left_rear_wheel', 'right_rear_wheel', 'left_steering_link',
                                        'right_steering_link', 'laser', 'imu_link', 'camera_link')},
        base_link='base_footprint', left_front_wheel='left_steering_link', right_front_wheel='right_steering_link',
        camera_optical='camera_link'))
    assert movable_joints(root) == MOVABLE


def test_prefix_names_every_link_joint_and_frame():
    root = robot(prefix='car7/')
    assert all(name.startswith('car7/') for name in links(root)), sorted(links(root))
    assert all(name.startswith('car7/') for name in joints(root)), sorted(joints(root))
    assert movable_joints(root) == {'car7/' + n for n in MOVABLE}
    drive = plugin_params(root, 'libconde_ackermann_drive.so')
    for key in ('leftSteeringJoint', 'rightSteeringJoint', 'leftFrontWheelJoint', 'rightFrontWheelJoint',
                'leftRearWheelJoint', 'rightRearWheelJoint'):
        assert drive[key] in joints(root), key
    assert drive['odometryFrame'] == 'car7/odom' and drive['robotBaseFrame'] == 'car7/base_footprint'
    assert plugin_params(root, 'libgazebo_ros_p3d.so')['bodyName'] == 'car7/base_footprint'
    assert plugin_params(root, 'libgazebo_ros_laser.so')['frameName'] == 'car7/laser'
    assert plugin_params(root, 'libgazebo_ros_imu_sensor.so')['frameName'] == 'car7/imu_link'
    assert plugin_params(root, 'libgazebo_ros_camera.so')['frameName'] == 'car7/camera_optical'
    for gazebo in root.findall('gazebo'):
        if gazebo.get('reference') is not None:
            assert gazebo.get('reference') in links(root), gazebo.get('reference')
    # the same robot otherwise: names differ by the prefix only
    plain = process()
    assert process(prefix='car7/').replace('car7/', '') == plain


def test_wheelbase_track_and_wheels_on_the_ground():
    root = robot()
    pos = {name: position_in_root(root, name) for name in
           ('left_rear_wheel', 'right_rear_wheel', 'left_front_wheel', 'right_front_wheel')}
    np.testing.assert_allclose(pos['left_rear_wheel'], [0, TRACK_M / 2, WHEEL_RADIUS_M], atol=1e-12)
    np.testing.assert_allclose(pos['right_rear_wheel'], [0, -TRACK_M / 2, WHEEL_RADIUS_M], atol=1e-12)
    np.testing.assert_allclose(pos['left_front_wheel'], [WHEELBASE_M, TRACK_M / 2, WHEEL_RADIUS_M], atol=1e-12)
    np.testing.assert_allclose(pos['right_front_wheel'], [WHEELBASE_M, -TRACK_M / 2, WHEEL_RADIUS_M], atol=1e-12)
    for name in pos:
        link = links(root)[name]
        cylinder = link.find('collision/geometry/cylinder')
        assert float(cylinder.get('radius')) == pytest.approx(WHEEL_RADIUS_M)
        # the cylinder's axis is the joint's axis (link y), so the wheel rolls forward about +y
        assert floats(link.find('collision/origin').get('rpy'))[0] == pytest.approx(-math.pi / 2)
        joint = joints(root)[name + '_joint']
        assert joint.get('type') == 'continuous'
        np.testing.assert_allclose(floats(joint.find('axis').get('xyz')), [0, 1, 0])
    for side in ('left', 'right'):
        hinge = joints(root)[side + '_steering_joint']
        np.testing.assert_allclose(floats(hinge.find('axis').get('xyz')), [0, 0, 1])


def test_steering_limits_give_the_f1tenth_centre_angle_by_ackermann_geometry():
    root = robot()
    for side in ('left', 'right'):
        limit = joints(root)[side + '_steering_joint'].find('limit')
        lower, upper = float(limit.get('lower')), float(limit.get('upper'))
        assert lower == -upper
        # The inner wheel at its limit: R = L / tan(inner) + d is the rear-axle radius of the
        # centre angle the drive plugin allows.
        centre = math.atan(WHEELBASE_M / (WHEELBASE_M / math.tan(upper) + TRACK_M / 2))
        assert centre == pytest.approx(MAX_STEERING_RAD, abs=1e-5)


def test_chassis_clears_the_ground_and_the_wheels():
    root = robot()
    box = links(root)['base_link'].find('collision')
    size = floats(box.find('geometry/box').get('size'))
    centre = floats(box.find('origin').get('xyz')) + position_in_root(root, 'base_link')
    assert centre[2] - size[2] / 2 > 0.05, 'chassis bottom must stay above the ground'
    inner_wheel_face_y = TRACK_M / 2 - float(
        links(root)['left_rear_wheel'].find('collision/geometry/cylinder').get('length')) / 2
    assert size[1] / 2 < inner_wheel_face_y
    # overall length of an F1/10 car (about 0.55-0.6 m), reaching past the front wheels
    assert 0.5 <= size[0] <= 0.6
    assert centre[0] + size[0] / 2 > WHEELBASE_M + WHEEL_RADIUS_M


def test_total_mass_is_an_f1tenth_car():
    root = robot()
    total = sum(mass(link) for link in links(root).values())
    assert total == pytest.approx(3.7, abs=0.05)
    for name, link in links(root).items():
        inertial = link.find('inertial')
        if inertial is None:
            continue
        i = {k: float(v) for k, v in inertial.find('inertia').attrib.items()}
        principal = sorted([i['ixx'], i['iyy'], i['izz']])
        assert principal[0] > 0 and principal[0] + principal[1] >= principal[2] * (1 - 1e-9), name


# ----------------------------------------------------------------------------------------------
# plugins and sensors
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize('drive, wheels', [('4wd', 'all'), ('2wd', 'rear')])
def test_drive_plugin(drive, wheels):
    root = robot(drive=drive)
    p = plugin_params(root, 'libconde_ackermann_drive.so')
    assert p['driveWheels'] == wheels
    assert {p[k] for k in ('leftSteeringJoint', 'rightSteeringJoint', 'leftFrontWheelJoint', 'rightFrontWheelJoint',
                           'leftRearWheelJoint', 'rightRearWheelJoint')} == MOVABLE
    assert p['commandTopic'] == 'ackermann_cmd' and p['twistTopic'] == 'cmd_vel'
    assert p['odometrySource'] == 'encoder' and p['robotBaseFrame'] == 'base_footprint'
    assert float(p['cmdTimeout']) > 0
    # PID efforts within the joints' effort limits
    wheel_limit = float(joints(root)['left_rear_wheel_joint'].find('limit').get('effort'))
    hinge_limit = float(joints(root)['left_steering_joint'].find('limit').get('effort'))
    assert float(p['wheelTorque']) <= wheel_limit and float(p['steeringTorque']) <= hinge_limit
    assert len(floats(p['wheelPidGains'])) == 3 and len(floats(p['steeringPidGains'])) == 3


def test_ground_truth_for_the_lap_timer():
    p = plugin_params(robot(), 'libgazebo_ros_p3d.so')
    assert p == {'bodyName': 'base_footprint', 'topicName': 'ground_truth/odom', 'frameName': 'world',
                 'updateRate': '50'}


def test_lidar_is_1081_beams_over_270_degrees_at_40_hz():
    root = robot()
    ray = sensor(root, 'ray')
    assert ray is not None
    assert root.find("gazebo/sensor[@type='ray']/..").get('reference') == 'laser'
    assert float(ray.find('update_rate').text) == 40
    horizontal = ray.find('ray/scan/horizontal')
    assert int(horizontal.find('samples').text) * int(horizontal.find('resolution').text) == 1081
    fov = float(horizontal.find('max_angle').text) - float(horizontal.find('min_angle').text)
    assert math.degrees(fov) == pytest.approx(270.0, abs=1e-5)
    assert float(ray.find('ray/range/min').text) < float(ray.find('ray/range/max').text)
    p = plugin_params(root, 'libgazebo_ros_laser.so')
    assert p == {'topicName': 'scan', 'frameName': 'laser'}
    # above the chassis top, so the car's own body is below the scan plane
    chassis = links(root)['base_link'].find('collision')
    top = (floats(chassis.find('origin').get('xyz'))[2] + floats(chassis.find('geometry/box').get('size'))[2] / 2
           + position_in_root(root, 'base_link')[2])
    assert position_in_root(root, 'laser')[2] > top


def test_imu_at_100_hz_and_camera_at_30_hz():
    root = robot()
    imu = sensor(root, 'imu')
    assert float(imu.find('update_rate').text) == 100
    assert plugin_params(root, 'libgazebo_ros_imu_sensor.so')['topicName'] == 'imu'
    camera = sensor(root, 'camera')
    assert float(camera.find('update_rate').text) == 30
    p = plugin_params(root, 'libgazebo_ros_camera.so')
    assert (p['cameraName'], p['imageTopicName'], p['cameraInfoTopicName'], p['frameName']) == (
        'camera', 'image_raw', 'camera_info', 'camera_optical')
    # looking ahead, from the front of the car
    assert position_in_root(root, 'camera_link')[0] > WHEELBASE_M


@pytest.mark.parametrize('name, sensor_type, link', [('lidar', 'ray', 'laser'), ('imu', 'imu', 'imu_link'),
                                                     ('camera', 'camera', 'camera_link')])
def test_each_sensor_follows_its_argument(name, sensor_type, link):
    off = robot(**{name: 'false'})
    assert sensor(off, sensor_type) is None
    assert link not in links(off)
    for other_name, other_type in (('lidar', 'ray'), ('imu', 'imu'), ('camera', 'camera')):
        if other_name != name:
            assert sensor(off, other_type) is not None, other_name
    assert sensor(robot(), sensor_type) is not None
