"""Where a car's wheels are, read from its URDF (the one source of the geometry), free of ROS.

The original ackermann_controller asked TF for these positions at start-up; reading the URDF
gives the same numbers without waiting for the simulation to publish joint states.
"""

import math
import xml.etree.ElementTree as ET

import numpy as np


class GeometryError(ValueError):
    """The URDF does not describe the car the controller needs."""


def _floats(text, count, what):
    try:
        values = [float(v) for v in (text or '').split()]
    except ValueError:
        values = []
    if len(values) != count:
        raise GeometryError('%s: expected %d numbers, got %r' % (what, count, text))
    return values


def _rotation(roll, pitch, yaw):
    """URDF rpy: fixed-axis roll about x, then pitch about y, then yaw about z."""
    cr, sr, cp, sp, cy, sy = (math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch),
                              math.cos(yaw), math.sin(yaw))
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    return rz @ ry @ rx


class UrdfTree:
    """Links and joints of a URDF document (its text)."""

    def __init__(self, urdf_xml):
        try:
            robot = ET.fromstring(urdf_xml)
        except ET.ParseError as e:
            raise GeometryError('malformed URDF: %s' % e) from None
        if robot.tag != 'robot':
            raise GeometryError('malformed URDF: the root element is <%s>, not <robot>' % robot.tag)
        self.links = {link.get('name') for link in robot.findall('link')}
        self.parent_joint = {}  # child link -> joint element
        for joint in robot.findall('joint'):
            child = joint.find('child')
            if child is not None:
                self.parent_joint[child.get('link')] = joint

    def _chain(self, link):
        """Joints from the root down to `link`."""
        if link not in self.links:
            raise GeometryError("the URDF has no link named '%s'" % link)
        chain = []
        while link in self.parent_joint:
            joint = self.parent_joint[link]
            chain.append(joint)
            link = joint.find('parent').get('link')
            if len(chain) > len(self.links):
                raise GeometryError('malformed URDF: the joints form a loop')
        return chain[::-1]

    def position_m(self, link):
        """Origin of `link` in the root link's frame with every joint at zero [m]."""
        rotation, position = np.eye(3), np.zeros(3)
        for joint in self._chain(link):
            origin = joint.find('origin')
            what = "joint '%s' <origin>" % joint.get('name')
            xyz = _floats(origin.get('xyz', '0 0 0'), 3, what + ' xyz') if origin is not None else [0, 0, 0]
            rpy = _floats(origin.get('rpy', '0 0 0'), 3, what + ' rpy') if origin is not None else [0, 0, 0]
            position = position + rotation @ np.array(xyz)
            rotation = rotation @ _rotation(*rpy)
        return position

    def _steering_limit(self, link):
        """(joint name, <limit> element) of the nearest revolute joint above `link` (its hinge)."""
        for joint in reversed(self._chain(link)):
            if joint.get('type') == 'revolute':
                limit = joint.find('limit')
                if limit is None:
                    raise GeometryError("joint '%s' has no <limit>" % joint.get('name'))
                return joint.get('name'), limit
        raise GeometryError("no revolute (steering) joint between the root and link '%s'" % link)

    def steering_limit_rad(self, link):
        """The smaller of |lower| and |upper| of the nearest revolute joint above `link` (its
        steering hinge)."""
        name, limit = self._steering_limit(link)
        lower = _floats(limit.get('lower', '0'), 1, "joint '%s' <limit> lower" % name)[0]
        upper = _floats(limit.get('upper', '0'), 1, "joint '%s' <limit> upper" % name)[0]
        return min(abs(lower), abs(upper))

    def steering_rate_limit_radps(self, link):
        """The <limit> velocity [rad/s] of the steering hinge above `link`; 0 when the URDF gives
        none (URDF's default: no limit)."""
        name, limit = self._steering_limit(link)
        rate = _floats(limit.get('velocity', '0'), 1, "joint '%s' <limit> velocity" % name)[0]
        if not (math.isfinite(rate) and rate >= 0):
            raise GeometryError("joint '%s' <limit> velocity: expected a number >= 0, got %r" % (name, rate))
        return rate


def car_dimensions(urdf_xml, left_front, right_front, left_rear, right_rear):
    """(wheelbase [m], half distance between the steering hinges [m], steering limit [rad]) from
    the positions of the four named links: the front ones at the hinges' origins, the rear ones
    at the rear wheels' centres (x forward, y left in the root link)."""
    tree = UrdfTree(urdf_xml)
    lf, rf, lr, rr = (tree.position_m(name) for name in (left_front, right_front, left_rear, right_rear))
    wheelbase_m = (lf[0] + rf[0]) / 2 - (lr[0] + rr[0]) / 2
    half_track_m = (lf[1] - rf[1]) / 2
    if not wheelbase_m > 0:
        raise GeometryError("the front links '%s', '%s' are not ahead of the rear links '%s', '%s' "
                            "(wheelbase %.4f m)" % (left_front, right_front, left_rear, right_rear, wheelbase_m))
    if not half_track_m > 0:
        raise GeometryError("link '%s' is not to the left of link '%s' (half track %.4f m)"
                            % (left_front, right_front, half_track_m))
    limit_rad = min(tree.steering_limit_rad(left_front), tree.steering_limit_rad(right_front))
    return wheelbase_m, half_track_m, limit_rad


def min_turning_radius_m(wheelbase_m, half_track_m, hinge_limit_rad):
    """The tightest circle [m] the rear-axle centre (base_footprint) of an Ackermann car can drive:
    the inner hinge at its limit turns about a point wheelbase / tan(limit) beside the inner rear
    wheel, half the track inside the rear-axle centre (Major Alvega: 0.32 / tan(45 deg) + 0.125 =
    0.445 m)."""
    if not 0 < hinge_limit_rad < math.pi / 2:
        raise GeometryError('steering limit %.4f rad: expected a number in (0, pi/2)' % hinge_limit_rad)
    return wheelbase_m / math.tan(hinge_limit_rad) + half_track_m


def car_turning_radius_m(urdf_xml, left_front, right_front, left_rear, right_rear):
    """(minimum turning radius of the rear-axle centre [m], what it comes from) of the car whose
    URDF is `urdf_xml`, its wheels the four named links (as car_dimensions)."""
    wheelbase_m, half_track_m, limit_rad = car_dimensions(urdf_xml, left_front, right_front, left_rear, right_rear)
    what = 'wheelbase %.3f m, hinges %.3f m apart, steering limit %.4f rad' % (
        wheelbase_m, 2 * half_track_m, limit_rad)
    return min_turning_radius_m(wheelbase_m, half_track_m, limit_rad), what
