"""Angles.  Pure Python, no ROS.

One wrap for every package that compares headings (the decision's course hold and arcs, Major
Alvega's odometry, the odometry evaluation, the sign-visibility geometry).
"""

import math


def wrap_rad(angle_rad):
    """The angle in [-pi, pi) [rad]; works on floats and element-wise on numpy arrays."""
    return (angle_rad + math.pi) % (2.0 * math.pi) - math.pi
