"""Wheelbase, hinge distance and steering limit read from a URDF (conde_major/urdf_geometry.py):
on the real Major Alvega description and on small made-up robots; the controller YAMLs of
this package name joints and links that the robot has."""

import math
import os
import xml.etree.ElementTree as ET

import pytest
import yaml

from conde_major.controller_config import load_wheel_config
from conde_major.ackermann_targets import max_centre_steering_rad
from conde_major.urdf_geometry import (GeometryError, UrdfTree, car_dimensions, car_turning_radius_m,
                                       min_turning_radius_m)
from conde_testing.ros_harness import xacro_finding

PACKAGE_DIR = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DESCRIPTION_DIR = os.path.join(os.path.dirname(os.path.dirname(PACKAGE_DIR)), 'urdf')
xacro = xacro_finding(DESCRIPTION_DIR)  # $(find conde_description) is this checkout's urdf/


@pytest.fixture(scope='module')
def major_urdf():
    path = os.path.join(DESCRIPTION_DIR, 'robots', 'major_alvega.urdf.xacro')
    return xacro.process_file(path, mappings={'cameras': 'false'}).toprettyxml(indent='  ')


def test_major_alvega_dimensions_from_its_urdf(major_urdf):
    c = load_wheel_config(os.path.join(PACKAGE_DIR, 'config', 'major_ackermann_controller.yaml'))
    wheelbase_m, half_track_m, limit_rad = car_dimensions(major_urdf, c.left_front.link, c.right_front.link,
                                                          c.left_rear.link, c.right_rear.link)
    assert wheelbase_m == pytest.approx(0.32, abs=1e-12)
    assert half_track_m == pytest.approx(0.125, abs=1e-12)
    assert limit_rad == pytest.approx(0.785398)


@pytest.mark.parametrize('yaml_name', ['major_joint_states.yaml'])
def test_controller_yamls_name_movable_joints_of_the_robot(major_urdf, yaml_name):
    with open(os.path.join(PACKAGE_DIR, 'config', yaml_name)) as f:
        controllers = yaml.safe_load(f)
    movable = {j.get('name') for j in ET.fromstring(major_urdf).findall('joint') if j.get('type') != 'fixed'}
    joints = {c['joint'] for c in controllers.values() if 'joint' in c}
    assert joints == movable
    assert controllers['joint_state_ctrlr'] == {'type': 'joint_state_controller/JointStateController',
                                                'publish_rate': 30}
    # The original's gains.
    for side in ('left', 'right'):
        pid = controllers[side + '_steering_ctrlr']['pid']
        assert (pid['p'], pid['d']) == (4.0, 1.0)
        assert pid['i'] == 0.0
        for axle in ('front', 'rear'):
            wheel = controllers['%s_%s_wheel_ctrlr' % (side, axle)]
            assert wheel['type'] == 'effort_controllers/JointVelocityController'
            assert wheel['pid'] == {'p': 0.5, 'i': 1.0, 'd': 0.0, 'i_clamp': 10.0}


def robot(front_x=0.3, rear_x=0.0, left_y=0.1, right_y=-0.1, hinge='revolute', rpy='0 0 1.5707963267948966'):
    """Base rotated by `rpy` on a fixed joint, four wheels, front ones on hinges."""
    def wheel(name, parent, xyz, kind='continuous', limit=''):
        return ('<link name="%s"/><joint name="%s_joint" type="%s"><parent link="%s"/><child link="%s"/>'
                '<origin xyz="%s"/>%s</joint>' % (name, name, kind, parent, name, xyz, limit))
    limit = '<limit lower="-0.5" upper="0.6" effort="1" velocity="1"/>'
    return ('<robot name="r"><link name="root"/><link name="base"/><joint name="b" type="fixed"><parent link="root"/>'
            '<child link="base"/><origin xyz="1 2 0" rpy="%s"/></joint>' % rpy
            + wheel('lh', 'base', '%g %g 0' % (front_x, left_y), hinge, limit if hinge == 'revolute' else '')
            + wheel('rh', 'base', '%g %g 0' % (front_x, right_y), hinge, limit if hinge == 'revolute' else '')
            + wheel('lf', 'lh', '0 0 0') + wheel('rf', 'rh', '0 0 0')
            + wheel('lr', 'base', '%g %g 0' % (rear_x, left_y)) + wheel('rr', 'base', '%g %g 0' % (rear_x, right_y))
            + '</robot>')


def test_positions_follow_rotated_joints():
    tree = UrdfTree(robot())
    assert list(tree.position_m('lf')) == pytest.approx([1 - 0.1, 2 + 0.3, 0])
    assert tree.steering_limit_rad('lf') == 0.5
    assert tree.steering_rate_limit_radps('lf') == 1.0


def test_major_alvega_steering_rate_limit(major_urdf):
    assert UrdfTree(major_urdf).steering_rate_limit_radps('left_front_wheel') == pytest.approx(4.553)


def test_a_hinge_without_a_velocity_limit_has_none():
    urdf = robot().replace(' velocity="1"', '')
    assert UrdfTree(urdf).steering_rate_limit_radps('rf') == 0.0


def test_dimensions_in_the_root_frame():
    # The base is turned 90 degrees in the root: x forward of the root is the base's -y.
    with pytest.raises(GeometryError, match="are not ahead of the rear links"):
        car_dimensions(robot(), 'lf', 'rf', 'lr', 'rr')
    assert car_dimensions(robot(rpy='0 0 0'), 'lf', 'rf', 'lr', 'rr') == pytest.approx((0.3, 0.1, 0.5))


@pytest.mark.parametrize('kwargs, links, message', [
    ({}, ('lf', 'rf', 'lr', 'nothing'), "the URDF has no link named 'nothing'"),
    ({'rpy': '0 0 0', 'front_x': -0.3}, ('lf', 'rf', 'lr', 'rr'),
     "the front links 'lf', 'rf' are not ahead of the rear links 'lr', 'rr' (wheelbase -0.3000 m)"),
    ({'rpy': '0 0 0'}, ('rf', 'lf', 'lr', 'rr'), "link 'rf' is not to the left of link 'lf' (half track -0.1000 m)"),
    ({'rpy': '0 0 0', 'hinge': 'continuous'}, ('lf', 'rf', 'lr', 'rr'),
     "no revolute (steering) joint between the root and link 'lf'"),
])
def test_errors_name_the_links(kwargs, links, message):
    with pytest.raises(GeometryError) as e:
        car_dimensions(robot(**kwargs), *links)
    assert str(e.value) == message


def test_malformed_urdf():
    with pytest.raises(GeometryError, match='malformed URDF'):
        UrdfTree('<robot><link name="a"></robot>')
    with pytest.raises(GeometryError, match='the root element is <sdf>'):
        UrdfTree('<sdf/>')


def test_major_alvega_minimum_turning_radius_from_its_urdf(major_urdf):
    c = load_wheel_config(os.path.join(PACKAGE_DIR, 'config', 'major_ackermann_controller.yaml'))
    radius_m, what = car_turning_radius_m(major_urdf, c.left_front.link, c.right_front.link, c.left_rear.link,
                                          c.right_rear.link)
    assert radius_m == pytest.approx(0.445, abs=1e-6)
    assert what == 'wheelbase 0.320 m, hinges 0.250 m apart, steering limit 0.7854 rad'
    # the adapter's largest centre angle (inner hinge at its limit) drives exactly this circle
    assert 0.32 / math.tan(max_centre_steering_rad(0.32, 0.125, 0.785398)) == pytest.approx(radius_m, abs=1e-9)


def test_minimum_turning_radius_of_a_made_up_car():
    # hinges 0.3 m ahead of the rear wheels, 0.2 m apart, the tighter side of the limit 0.5 rad
    radius_m, _ = car_turning_radius_m(robot(rpy='0 0 0'), 'lf', 'rf', 'lr', 'rr')
    assert radius_m == pytest.approx(0.3 / math.tan(0.5) + 0.1)
    with pytest.raises(GeometryError, match='steering limit 0.0000 rad'):
        min_turning_radius_m(0.3, 0.1, 0.0)
