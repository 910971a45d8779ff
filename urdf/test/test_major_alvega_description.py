"""Checks of the Major Alvega description (robots/major_alvega.urdf.xacro) against the facts of
the original robot (its major.xacro and controller YAML).

Run from the repository root:  /usr/bin/python3 -m pytest urdf/test

The xacro is processed with the xacro Python module (PyPI xacro 1.13, ROS 1 line); the URDF is
parsed with xml.etree and validated with check_urdf (liburdfdom-tools).
"""

import math
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from description_helpers import (XacroRobot, assert_frame_tree, assert_no_leftover_xacro, check_urdf, floats, joints,
                                 links, mass, movable_joints, plugin_params)

ROBOT = XacroRobot('major_alvega.urdf.xacro')
process = ROBOT.process
robot = ROBOT.robot

WHEELBASE_M = 0.32
TRACK_M = 0.25
WHEEL_RADIUS_M = 0.05
WHEEL_WIDTH_M = 0.045
WHEELS = ('left_front_wheel', 'right_front_wheel', 'left_rear_wheel', 'right_rear_wheel')
MOVABLE = {'left_steering_joint', 'right_steering_joint', 'left_front_wheel_joint', 'right_front_wheel_joint',
           'left_rear_wheel_joint', 'right_rear_wheel_joint'}
MASSES_KG = {'chassis': 0.388, 'top_chassis': 0.5, 'left_front_wheel': 0.29, 'right_front_wheel': 0.29,
             'left_rear_wheel': 0.29, 'right_rear_wheel': 0.29, 'left_steering_link': 0.001,
             'right_steering_link': 0.001, 'camera_link': 0.1, 'top_camera_link': 0.1}
# (link, image topic, info topic, width, height, joint xyz in chassis, pitch, distortion k1 k2 k3 p1 p2, centre)
CAMERAS = [
    ('camera_link', 'major_tracking_camera', 'camera_info', 160, 120, (0.295, 0, 0.535), 0.76,
     (-0.2673, 0.0629, -0.0061, 0.0012, -9.1477e-4), (0.501996094, 0.4585875)),
    ('top_camera_link', 'major_top_camera', 'top_camera_info', 320, 240, (0.288, 0, 0.75), -0.3,
     (-0.254536654032040, 0.052707476272924, 0.004060325839474, 0.001216492819178, 0.001034739611621),
     (0.486, 0.432)),
]


def rotation(rpy):
    """URDF rpy (fixed axes x, y, z) as a rotation matrix."""
    (cr, cp, cy), (sr, sp, sy) = np.cos(rpy), np.sin(rpy)
    return (np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]]) @ np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
            @ np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]]))


def pose_in_root(root, link_name):
    """(position, rotation) of a link in base_link with every joint at zero."""
    parents = {j.find('child').get('link'): j for j in root.findall('joint')}
    chain = []
    while link_name in parents:
        chain.append(parents[link_name])
        link_name = parents[link_name].find('parent').get('link')
    position, rot = np.zeros(3), np.eye(3)
    for joint in reversed(chain):
        origin = joint.find('origin')
        xyz = floats(origin.get('xyz', '0 0 0')) if origin is not None else np.zeros(3)
        rpy = floats(origin.get('rpy', '0 0 0')) if origin is not None else np.zeros(3)
        position, rot = position + rot @ xyz, rot @ rotation(rpy)
    return position, rot


def inertia(link):
    return {k: float(v) for k, v in link.find('inertial/inertia').attrib.items()}


def surface(root, link):
    blocks = root.findall("gazebo[@reference='%s']" % link)
    return {c.tag: c.text.strip() for g in blocks for c in g if c.tag in ('mu1', 'mu2')}


# ----------------------------------------------------------------------------------------------
# validity and arguments
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize('cameras', ['true', 'false'])
def test_check_urdf_accepts_the_robot(cameras, tmp_path):
    assert 'root Link: base_link' in check_urdf(process(cameras=cameras), tmp_path, 'major_alvega.urdf')


def test_invalid_cameras_argument_is_rejected_naming_it():
    with pytest.raises(Exception, match='ERROR_arg_cameras_must_be_true_or_false'):
        process(cameras='yes')


def test_generated_urdf_has_no_leftover_xacro():
    assert_no_leftover_xacro(process())


# ----------------------------------------------------------------------------------------------
# links, joints, geometry
# ----------------------------------------------------------------------------------------------
def test_frame_tree_and_joint_names():
    root = robot()
    assert root.get('name') == 'major_alvega'
    assert links(root)['base_link'].find('inertial') is None, 'base_link has no inertial, as in the original'
    assert_frame_tree(root, 'base_link', dict(
        {link: 'chassis' for link in ('top_chassis', 'bar_chassis', 'left_rear_wheel', 'right_rear_wheel',
                                      'left_steering_link', 'right_steering_link', 'camera_link', 'top_camera_link')},
        chassis='base_link', base_footprint='base_link',
        left_front_wheel='left_steering_link', right_front_wheel='right_steering_link',
        camera_link_optical='camera_link', top_camera_link_optical='top_camera_link'))
    assert movable_joints(root) == MOVABLE
    np.testing.assert_allclose(pose_in_root(root, 'chassis')[0], [0, 0, 0])
    np.testing.assert_allclose(pose_in_root(root, 'base_footprint')[0], [-WHEELBASE_M / 2, 0, 0])  # rear axle


def test_wheelbase_track_and_wheels_on_the_ground():
    root = robot()
    pos = {name: pose_in_root(root, name)[0] for name in WHEELS}
    half_l, half_t = WHEELBASE_M / 2, TRACK_M / 2
    np.testing.assert_allclose(pos['left_front_wheel'], [half_l, half_t, WHEEL_RADIUS_M], atol=1e-12)
    np.testing.assert_allclose(pos['right_front_wheel'], [half_l, -half_t, WHEEL_RADIUS_M], atol=1e-12)
    np.testing.assert_allclose(pos['left_rear_wheel'], [-half_l, half_t, WHEEL_RADIUS_M], atol=1e-12)
    np.testing.assert_allclose(pos['right_rear_wheel'], [-half_l, -half_t, WHEEL_RADIUS_M], atol=1e-12)
    for side in ('left', 'right'):
        hinge = joints(root)[side + '_steering_joint']
        np.testing.assert_allclose(floats(hinge.find('origin').get('xyz')),
                                   [half_l, half_t if side == 'left' else -half_t, WHEEL_RADIUS_M])
        np.testing.assert_allclose(floats(hinge.find('axis').get('xyz')), [0, 0, 1])


@pytest.mark.parametrize('wheel', WHEELS)
def test_wheels_roll_forward_about_the_cars_y_axis(wheel):
    root = robot()
    joint = joints(root)[wheel + '_joint']
    assert joint.get('type') == 'continuous'
    # The original's frames: joint rpy (pi/2, 0, 0) and axis (0 0 -1), i.e. the car's +y.
    np.testing.assert_allclose(floats(joint.find('origin').get('rpy')), [math.pi / 2, 0, 0], atol=1e-9)
    np.testing.assert_allclose(floats(joint.find('axis').get('xyz')), [0, 0, -1])
    _, rot = pose_in_root(root, wheel)
    np.testing.assert_allclose(rot @ floats(joint.find('axis').get('xyz')), [0, 1, 0], atol=1e-9)
    cylinder = links(root)[wheel].find('collision/geometry/cylinder')
    assert float(cylinder.get('radius')) == pytest.approx(WHEEL_RADIUS_M)
    assert float(cylinder.get('length')) == pytest.approx(WHEEL_WIDTH_M)
    assert links(root)[wheel].find('collision/origin') is None  # the cylinder's axis is the wheel link's z
    limit = joint.find('limit')
    assert float(limit.get('effort')) == pytest.approx(5.12766)
    assert float(limit.get('velocity')) == pytest.approx(244.8696)


@pytest.mark.parametrize('side', ['left', 'right'])
def test_steering_limits_are_the_servo_figures(side):
    limit = joints(robot())[side + '_steering_joint'].find('limit')
    assert float(limit.get('lower')) == pytest.approx(-0.785398)
    assert float(limit.get('upper')) == pytest.approx(0.785398)
    assert float(limit.get('effort')) == pytest.approx(0.5649)
    assert float(limit.get('velocity')) == pytest.approx(4.553)


@pytest.mark.parametrize('cameras', ['true', 'false'])
def test_masses_of_the_original(cameras):
    root = robot(cameras=cameras)
    got = {name: mass(link) for name, link in links(root).items() if mass(link) > 0}
    assert got == pytest.approx(MASSES_KG)
    assert sum(got.values()) == pytest.approx(2.25)  # reference: about 2.25 kg


def test_inertias():
    root = robot()
    # Uniform box of the chassis; the plate with the original's 0.025 m macro height.
    assert inertia(links(root)['chassis']) == pytest.approx(
        {'ixx': 6.539e-4, 'iyy': 3.331e-3, 'izz': 3.945e-3, 'ixy': 0, 'ixz': 0, 'iyz': 0}, rel=1e-3, abs=1e-12)
    assert inertia(links(root)['top_chassis']) == pytest.approx(
        {'ixx': 3.776e-3, 'iyy': 1.0443e-2, 'izz': 1.4167e-2, 'ixy': 0, 'ixz': 0, 'iyz': 0}, rel=1e-3, abs=1e-12)
    # The steering links' "null inertial": 1 g, 1e-3 kg m^2 about each axis.
    for side in ('left', 'right'):
        assert inertia(links(root)[side + '_steering_link']) == pytest.approx(
            {'ixx': 1e-3, 'iyy': 1e-3, 'izz': 1e-3, 'ixy': 0, 'ixz': 0, 'iyz': 0})
    # Wheels: a tube from the hub (0.04 m) to the wheel radius (0.05 m); spin axis = link z.
    for wheel in WHEELS:
        i = inertia(links(root)[wheel])
        assert i['izz'] == pytest.approx(0.29 * (0.04 ** 2 + 0.05 ** 2) / 2)
        assert i['ixx'] == i['iyy'] == pytest.approx(0.29 * (3 * (0.04 ** 2 + 0.05 ** 2) + 0.045 ** 2) / 12)
        # The wheel PID (p 0.5 at a 1 ms step) is explicit: stable only while p * step < 2 * inertia.
        assert 0.5 * 0.001 < 2 * i['izz']
    # The hinge PID (d 1 at a 1 ms step) sees the steering link and the wheel about z.
    hinge_inertia = 1e-3 + inertia(links(root)['left_front_wheel'])['ixx']
    assert 1.0 * 0.001 < 2 * hinge_inertia


def test_friction():
    root = robot()
    for wheel in WHEELS:
        assert surface(root, wheel) == {'mu1': '0.5', 'mu2': '0.5'}, wheel
    for side in ('left', 'right'):
        assert surface(root, side + '_steering_link') == {'mu1': '0.6', 'mu2': '0.6'}


def test_transmissions_on_all_six_joints():
    root = robot()
    by_joint = {}
    for t in root.findall('transmission'):
        assert t.find('type').text.strip() == 'transmission_interface/SimpleTransmission'
        joint = t.find('joint')
        assert joint.find('hardwareInterface').text.strip() == 'hardware_interface/EffortJointInterface'
        actuator = t.find('actuator')
        assert float(actuator.find('mechanicalReduction').text) == 1
        by_joint[joint.get('name')] = actuator.get('name')
    assert set(by_joint) == MOVABLE
    assert by_joint['left_rear_wheel_joint'] == by_joint['right_rear_wheel_joint'] == 'rear_motor'
    assert len(set(by_joint.values())) == 5


def test_ros_control_and_ground_truth_plugins():
    root = robot()
    assert plugin_params(root, 'libgazebo_ros_control.so') == {
        'robotNamespace': '/', 'robotSimType': 'gazebo_ros_control/DefaultRobotHWSim', 'legacyModeNS': 'true'}
    p3d = plugin_params(root, 'libgazebo_ros_p3d.so')
    assert (p3d['bodyName'], p3d['topicName'], p3d['frameName'], float(p3d['updateRate'])) == (
        'base_link', 'odom_ground_truth', 'map', 50.0)


# ----------------------------------------------------------------------------------------------
# cameras
# ----------------------------------------------------------------------------------------------
@pytest.mark.parametrize('link, name, info_topic, width, height, xyz, pitch, distortion, centre', CAMERAS,
                         ids=[c[1] for c in CAMERAS])
def test_wide_angle_cameras(link, name, info_topic, width, height, xyz, pitch, distortion, centre):
    root = robot()
    joint = joints(root)[link + '_joint']
    assert joint.find('parent').get('link') == 'chassis'
    np.testing.assert_allclose(floats(joint.find('origin').get('xyz')), xyz)
    np.testing.assert_allclose(floats(joint.find('origin').get('rpy')), [0, pitch, 0])
    optical = joints(root)[link + '_optical_joint']
    np.testing.assert_allclose(floats(optical.find('origin').get('rpy')), [-math.pi / 2, 0, -math.pi / 2])

    sensors = root.findall("gazebo[@reference='%s']/sensor" % link)
    assert len(sensors) == 1
    sensor = sensors[0]
    assert sensor.get('type') == 'wideanglecamera'
    assert float(sensor.find('update_rate').text) == 30
    camera = sensor.find('camera')
    assert float(camera.find('horizontal_fov').text) == 2.6
    assert (int(camera.find('image/width').text), int(camera.find('image/height').text),
            camera.find('image/format').text) == (width, height, 'R8G8B8')
    assert (float(camera.find('clip/near').text), float(camera.find('clip/far').text)) == (0.1, 100)
    assert (camera.find('noise/type').text, float(camera.find('noise/mean').text),
            float(camera.find('noise/stddev').text)) == ('gaussian', 0.0, 0.007)
    d = camera.find('distortion')
    assert tuple(float(d.find(k).text) for k in ('k1', 'k2', 'k3', 'p1', 'p2')) == distortion
    assert tuple(floats(d.find('center').text)) == centre
    lens = {c.tag: c.text.strip() for c in camera.find('lens')}
    assert lens == {'type': 'stereographic', 'scale_to_hfov': 'true', 'cutoff_angle': '1.5707',
                    'env_texture_size': '256'}
    plugin = {c.tag: (c.text or '').strip() for c in sensor.find('plugin')}
    assert sensor.find('plugin').get('filename') == 'libgazebo_ros_camera.so'
    assert (plugin['cameraName'], plugin['imageTopicName'], plugin['cameraInfoTopicName'], plugin['frameName'],
            float(plugin['updateRate'])) == (name, 'image_raw', info_topic, link + '_optical', 0.0)


def test_cameras_false_keeps_the_bodies_without_sensors():
    off = robot(cameras='false')
    assert off.findall('gazebo/sensor') == []
    assert {'camera_link', 'top_camera_link', 'camera_link_optical', 'top_camera_link_optical'} <= set(links(off))
    # otherwise the same robot
    assert len(robot().findall('gazebo/sensor')) == 2
    on_links = {n: ET.tostring(link) for n, link in links(robot()).items()}
    assert {n: ET.tostring(link) for n, link in links(off).items()} == on_links
